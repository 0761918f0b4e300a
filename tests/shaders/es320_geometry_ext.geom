#version 310 es
#extension GL_EXT_geometry_shader : require
precision highp float;
layout(lines) in;
layout(line_strip, max_vertices = 2) out;
uniform mat4 u_viewProj;
in vec3 v_world[];
void main()
{
    for (int i = 0; i < 2; i++) {
        gl_Position = u_viewProj * vec4(v_world[i], 1.0);
        EmitVertex();
    }
    EndPrimitive();
}
