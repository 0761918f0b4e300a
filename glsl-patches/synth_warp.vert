#version 330 core
// One leaf quad of a rendered view, moved into a target view: each corner by its own
// disparity (u_target - u_source)(s·p + f), in tile pixels. Drawn as a 4-vertex strip per
// instance; the leaf comes in as instanced attributes.
layout(location = 0) in uvec4 a_rect;
layout(location = 1) in vec4 a_corners;
uniform vec2 u_tile;
uniform float u_du;
// (s, f) times half the tile width: pixels per unit of parallax, and of focus.
uniform vec2 u_px;
// Half a pixel of overlap closes T-junction cracks between cells of different sizes.
uniform float u_margin;
out vec2 v_uv;
flat out int v_stretched;
flat out int v_cell_x;

void main()
{
    vec2 corner = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1));
    vec2 src = vec2(a_rect.xy) + corner * vec2(a_rect.zw);
    vec4 disp = u_du * (u_px.x * a_corners + u_px.y);
    float d = corner.y == 0.0 ? (corner.x == 0.0 ? disp.x : disp.y) : (corner.x == 0.0 ? disp.z : disp.w);
    // Border vertices never move inwards: the edge quad stretches instead of leaving a hole.
    if (src.x <= 0.0) d = min(d, 0.0);
    if (src.x >= u_tile.x) d = max(d, 0.0);
    // A one-pixel leaf (only depth edges split that far) widened by more than a pixel spans
    // a disocclusion: it shows the background side rather than smearing the foreground.
    float stretch = max(disp.y - disp.x, disp.w - disp.z);
    v_stretched = a_rect.z == 1u && stretch > 1.0 ? 1 : 0;
    v_cell_x = int(a_rect.x);
    float x = src.x + d + u_margin * (corner.x * 2.0 - 1.0);
    v_uv = src / u_tile;
    gl_Position = vec4(vec2(x, src.y) / u_tile * 2.0 - 1.0, 0.0, 1.0);
}
