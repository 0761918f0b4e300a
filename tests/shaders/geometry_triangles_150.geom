#version 150
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
in vec3 vNormal[];
out vec3 gNormal;
uniform mat4 projection;
void main()
{
    for (int i = 0; i < 3; i++) {
        gNormal = vNormal[i];
        gl_Position = projection * gl_in[i].gl_Position;
        EmitVertex();
    }
    EndPrimitive();
}
