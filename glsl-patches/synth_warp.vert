#version 330 core
// One leaf quad of a rendered view, moved into a target view: each corner by its own
// disparity (u_target - u_source)(s·p + f), in tile pixels, and at its own window depth (the
// view shift leaves z and w alone; over a plane, window depth is affine in screen space, so
// interpolating it is exact and the fragment shader writes no depth).
// Six vertices (two triangles) per leaf, fetched from the leaf list by gl_VertexID.
uniform usamplerBuffer u_leaves;
uniform sampler2DArray u_parallax;
uniform sampler2DArray u_depth;
uniform int u_layer;
uniform vec2 u_tile;
uniform float u_du;
// (s, f) times half the tile width: pixels per unit of parallax, and of focus.
uniform vec2 u_px;
// Half a pixel of overlap closes T-junction cracks between cells of different sizes.
uniform float u_margin;
// Towards the far side, in window depth: +2^-14, or negative under reversed-Z.
uniform float u_far_bias;
// 1 when window depth is z_ndc (glClipControl GL_ZERO_TO_ONE), else 0.
uniform int u_zero_to_one;
// Pixels the viewport extends beyond each side of the tile (the scissor cuts at the tile):
// a quad moved partly out of the tile is then cut by the rasterizer, not clipped, which
// llvmpipe does on a slow path whose cost grows with the whole draw.
uniform float u_overhang;
out vec2 v_uv;

void main()
{
    int leaf = gl_VertexID / 6;
    const int corners[6] = int[6](0, 1, 2, 2, 1, 3);
    int k = corners[gl_VertexID - leaf * 6];
    uvec4 a_rect = texelFetch(u_leaves, leaf * 3);
    vec4 a_corners = uintBitsToFloat(texelFetch(u_leaves, leaf * 3 + 1));
    vec4 a_depths = uintBitsToFloat(texelFetch(u_leaves, leaf * 3 + 2));
    vec2 corner = vec2(float(k & 1), float(k >> 1));
    vec2 src = vec2(a_rect.xy) + corner * vec2(a_rect.zw);
    vec4 disp = u_du * (u_px.x * a_corners + u_px.y);
    float d = disp[k];
    float depth = a_depths[k];
    // Border vertices never move inwards: the edge quad stretches instead of leaving a hole.
    if (src.x <= 0.0) d = min(d, 0.0);
    if (src.x >= u_tile.x) d = max(d, 0.0);
    v_uv = src / u_tile;
    // A one-pixel-wide leaf (only depth edges split that far) widened by more than a pixel spans
    // a disocclusion: it shows the farther of its row's neighbours, stretched, behind
    // everything actually seen there, rather than smearing the foreground.
    float stretch = max(disp.y - disp.x, disp.w - disp.z);
    if (a_rect.z == 1u && stretch > 1.0) {
        int w = int(u_tile.x);
        // This vertex's row of the leaf (columns can be many rows tall).
        int row = int(a_rect.y) + int(corner.y) * (int(a_rect.w) - 1);
        int x = int(a_rect.x);
        int left = max(x - 1, 0), right = min(x + 1, w - 1);
        float pl = texelFetch(u_parallax, ivec3(left, row, u_layer), 0).r;
        float pr = texelFetch(u_parallax, ivec3(right, row, u_layer), 0).r;
        int far = pl >= pr ? left : right;
        // Down the column, rows map to themselves: fragment centres sample row centres.
        v_uv = vec2((float(far) + 0.5) / u_tile.x, src.y / u_tile.y);
        depth = clamp(texelFetch(u_depth, ivec3(far, row, u_layer), 0).r + u_far_bias, 0.0, 1.0);
    }
    float x = src.x + d + u_margin * (corner.x * 2.0 - 1.0);
    float z = u_zero_to_one == 1 ? depth : 2.0 * depth - 1.0;
    vec2 viewport = u_tile + vec2(2.0 * u_overhang, 0.0);
    gl_Position = vec4((vec2(x + u_overhang, src.y) / viewport) * 2.0 - 1.0, z, 1.0);
}
