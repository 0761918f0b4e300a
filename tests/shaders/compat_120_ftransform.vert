#version 120
// Invariant with the fixed-function pipeline, as multipass legacy renderers require.
varying vec2 uv;
void main()
{
    uv = gl_MultiTexCoord0.st;
    gl_FrontColor = gl_Color;
    gl_Position = ftransform();
}
