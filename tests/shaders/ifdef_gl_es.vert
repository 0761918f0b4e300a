// Shared between desktop GL 2.1 and GLES 2.0 builds: no #version on purpose.
#ifdef GL_ES
precision mediump float;
#define LOWP lowp
#else
#define LOWP
#endif
attribute vec2 a_pos;
attribute vec4 a_color;
uniform mat4 u_matrix;
varying LOWP vec4 v_color;
void main()
{
    v_color = a_color;
    gl_Position = u_matrix * vec4(a_pos, 0.0, 1.0);
}
