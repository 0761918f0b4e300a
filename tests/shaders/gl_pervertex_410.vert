#version 410 core
out gl_PerVertex
{
    vec4 gl_Position;
    float gl_PointSize;
};
layout(location = 0) in vec4 pos;
uniform mat4 MVP;
void main()
{
    gl_PointSize = 1.0;
    gl_Position = MVP * pos;
}
