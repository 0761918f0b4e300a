#version 140
in vec4 position;
in vec2 texcoord;
out vec2 v_texcoord;
uniform mat4 mvp;
void main()
{
    v_texcoord = texcoord;
    gl_Position = mvp * position;
}
