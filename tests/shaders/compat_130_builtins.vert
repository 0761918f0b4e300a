#version 130
in vec4 extra;
out vec4 color;
void main()
{
    color = gl_Color + extra;
    gl_Position = gl_ProjectionMatrix * gl_ModelViewMatrix * gl_Vertex;
}
