#version 330 core
// One triangle covering the viewport, from gl_VertexID alone: draw with
// glDrawArrays(GL_TRIANGLES, 0, 3) and any (empty) VAO bound, no attributes.
// A single triangle instead of a quad avoids the doubled fragments along the diagonal.
// u_quad_z (NDC, 0 unless set) puts it at a depth: the comfort pass draws at the depth of a
// disparity threshold with the depth test on, so pixels on the wrong side are never shaded.
uniform float u_quad_z;

void main()
{
    vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(corner * 2.0 - 1.0, u_quad_z, 1.0);
}
