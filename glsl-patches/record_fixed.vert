#version 120
// The disparity record of a fixed-function draw (src/multiview/replay/record_fixed.rs): the
// draw is made again with this program, depth-tested EQUAL against what it just wrote, so
// every pixel it left visible gets the parallax its sheared projection gave it, 1 - c/w
// (c = 0: attached to the camera, at infinity). ftransform() is invariant with the fixed
// function's transform, so the depths match bit for bit. A draw that writes no depth is
// drawn again under its own depth state, and its coverage (the fixed function's alpha, see
// the fragment shader) decides where it is what the viewer sees.
uniform float holoinject_c;
// The alpha's source: 0 the vertex colour, 1 the front material's diffuse (lighting on
// without colour material).
uniform int holoinject_lit;
varying float holoinject_parallax_w;
void main()
{
    gl_Position = ftransform();
    gl_ClipVertex = gl_ModelViewMatrix * gl_Vertex;
    holoinject_parallax_w = gl_Position.w - holoinject_c;
    gl_FrontColor = vec4(1.0, 1.0, 1.0, holoinject_lit == 1 ? gl_FrontMaterial.diffuse.a : gl_Color.a);
    gl_TexCoord[0] = gl_TextureMatrix[0] * gl_MultiTexCoord0;
}
