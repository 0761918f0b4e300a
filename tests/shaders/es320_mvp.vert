#version 320 es
precision mediump float;
layout(location = 0) in vec4 pos;
layout(location = 1) in vec4 col;
uniform highp mat4 mvp;
out vec4 v_col;
void main()
{
    v_col = col;
    gl_Position = mvp * pos;
}
