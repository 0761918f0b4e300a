#version 330 core
layout (location = 0) in vec3 aPos;
uniform mat4 viewProjection;
out vec3 dir;
void main()
{
    dir = aPos;
    gl_Position = viewProjection * vec4(aPos, 1.0);
    gl_Position.z = gl_Position.w;
}
