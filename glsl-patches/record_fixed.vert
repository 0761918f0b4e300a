#version 120
// The disparity record of a fixed-function draw (src/multiview/replay/record_fixed.rs): the
// draw is made again with this program, depth-tested EQUAL against what it just wrote, so
// every pixel it left visible gets the parallax its sheared projection gave it, 1 - c/w
// (c = 0: attached to the camera, at infinity). ftransform() is invariant with the fixed
// function's transform, so the depths match bit for bit.
uniform float holoinject_c;
varying float holoinject_parallax_w;
void main()
{
    gl_Position = ftransform();
    gl_ClipVertex = gl_ModelViewMatrix * gl_Vertex;
    holoinject_parallax_w = gl_Position.w - holoinject_c;
}
