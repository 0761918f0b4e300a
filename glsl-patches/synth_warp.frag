#version 330 core
// The warped colour; depth comes interpolated from the quad's corners (see the vertex shader).
uniform sampler2DArray u_color;
uniform int u_layer;
in vec2 v_uv;
out vec4 o_color;

void main()
{
    o_color = texture(u_color, vec3(v_uv, float(u_layer)));
}
