#version 330 core
void main()
{
    gl_PointSize = 64.0;
    gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
}
