#version 310 es
layout(std140, binding = 0) uniform Camera {
    mat4 viewProj;
    vec4 eye;
} cam;
uniform mat4 model;
layout(location = 0) in vec3 pos;
out vec3 toEye;
void main()
{
    vec4 world = model * vec4(pos, 1.0);
    toEye = cam.eye.xyz - world.xyz;
    gl_Position = cam.viewProj * world;
}
