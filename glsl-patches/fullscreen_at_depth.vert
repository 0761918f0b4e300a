#version 330 core
// fullscreen.vert at a chosen depth: the comfort pass draws its tile at the window depth of
// a disparity threshold with the depth test on, so the rasteriser drops the pixels on the
// wrong side of it before any shading (u_quad_z is in NDC, the CPU maps the window depth).
uniform float u_quad_z;

void main()
{
    vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(corner * 2.0 - 1.0, u_quad_z, 1.0);
}
