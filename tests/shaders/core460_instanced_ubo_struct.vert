#version 460 core
struct Object {
    mat4 model;
    vec4 tint;
};
layout(std140, binding = 1) uniform Transforms {
    mat4 proj;
    mat4 view;
} xf;
uniform Object obj;
layout(location = 0) in vec3 position;
layout(location = 0) out vec4 tint;
void main()
{
    tint = obj.tint;
    mat4 vp = xf.proj * xf.view;
    gl_Position = vp * obj.model * vec4(position, 1.0);
}
