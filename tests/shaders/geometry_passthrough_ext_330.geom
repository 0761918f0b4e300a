#version 330 core
#ifdef GL_ARB_gpu_shader5
#extension GL_ARB_gpu_shader5 : enable
#endif
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
out vec3 bary;
void main()
{
    for (int i = 0; i < 3; i++) {
        bary = vec3(0.0);
        bary[i] = 1.0;
        gl_Position = gl_in[i].gl_Position;
        EmitVertex ();
    }
    EndPrimitive();
}
