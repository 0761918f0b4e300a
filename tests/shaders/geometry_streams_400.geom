#version 400 core
layout(points) in;
layout(points, max_vertices = 2) out;
layout(stream = 0) out vec4 color;
layout(stream = 1) out vec4 captured;
uniform mat4 mvp;
void main()
{
    color = vec4(1.0);
    gl_Position = mvp * gl_in[0].gl_Position;
    EmitStreamVertex(0);
    EndStreamPrimitive(0);
    captured = gl_in[0].gl_Position;
    EmitStreamVertex(1);
    EndStreamPrimitive(1);
}
