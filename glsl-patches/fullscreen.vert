#version 330 core
// One triangle covering the viewport, from gl_VertexID alone: draw with
// glDrawArrays(GL_TRIANGLES, 0, 3) and any (empty) VAO bound, no attributes.
// A single triangle instead of a quad avoids the doubled fragments along the diagonal.

void main()
{
    vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
