#version 120
// See record_fixed.vert: (p, recorded, 0, 1) into the record's draw buffer, the only one on.
varying float holoinject_parallax_w;
void main()
{
    gl_FragData[7] = vec4(holoinject_parallax_w * gl_FragCoord.w, 1.0, 0.0, 1.0);
}
