#version 330 core
layout(location = 0) in vec3 pos;
uniform mat4 u_viewProj;
uniform mat4 u_model;
vec4 toClip(vec3 p)
{
    return u_viewProj * u_model * vec4(p, 1.0);
}
void main()
{
    gl_Position = toClip(pos);
}
