#version 120
// See record_fixed.vert: (p, recorded, 0, coverage) into the record's draw buffer, the only
// one on. Coverage: the fixed function's output alpha as unit 0 makes it contributes at all
// (>= 1/255; `holoinject_texture`: -1 the draw does not blend, 0 the colour's alpha alone,
// 1 modulate, 2 replace), the shader record's rule for the app's colour.
uniform int holoinject_texture;
uniform sampler2D holoinject_unit0;
varying float holoinject_parallax_w;
void main()
{
    float a = gl_Color.a;
    if (holoinject_texture == 1) {
        a *= texture2D(holoinject_unit0, gl_TexCoord[0].st).a;
    } else if (holoinject_texture == 2) {
        a = texture2D(holoinject_unit0, gl_TexCoord[0].st).a;
    } else if (holoinject_texture < 0) {
        a = 1.0;
    }
    gl_FragData[7] = vec4(holoinject_parallax_w * gl_FragCoord.w, 1.0, 0.0, a >= 1.0 / 255.0 ? 1.0 : 0.0);
}
