#version 430 core
// The adaptive quad grid (Didyk et al. 2011): one dispatch per pyramid level, coarsest
// first. A cell is flat enough when, in pixels of the outermost target view, its parallax
// range is within the threshold (Didyk's test), or a quad's interpolation error over it is
// (second-difference bound times cell²/8: planes warp exactly whatever their depth range).
// It is a leaf when it is flat enough and its parent is not (both bounds only shrink towards
// the leaves, so every ancestor was split). Cells of 2x2 pixels still too deep split into single pixels.
// Leaves are appended to a list that feeds one draw per target view; each carries
// the parallax at its four corners (the farthest of the four pixels around each corner, so
// quads on a depth edge stretch across the disocclusion with the background).
layout(local_size_x = 8, local_size_y = 8) in;

uniform sampler2DArray u_parallax;
uniform sampler2DArray u_level;
uniform sampler2DArray u_parent;
uniform sampler2DArray u_depth;
uniform int u_layer;
uniform int u_cell;
uniform int u_top;
uniform float u_scale;
uniform float u_threshold;
uniform ivec2 u_tile;

struct Leaf {
    uvec4 rect;
    vec4 corners;
    vec4 depths;
};
layout(std430, binding = 0) buffer Leaves { Leaf leaves[]; };
layout(std430, binding = 1) buffer Command { uint count; uint instances; uint first; uint base; } command;

// The parallax and window depth of the farthest of the four pixels around vertex v.
vec2 corner(ivec2 v)
{
    vec2 c = vec2(-3.0e38, 1.0);
    for (int y = -1; y <= 0; y++) {
        for (int x = -1; x <= 0; x++) {
            ivec3 q = ivec3(clamp(v + ivec2(x, y), ivec2(0), u_tile - 1), u_layer);
            float p = texelFetch(u_parallax, q, 0).r;
            if (p > c.x) {
                c = vec2(p, texelFetch(u_depth, q, 0).r);
            }
        }
    }
    return c;
}

void emit(ivec2 xy, ivec2 size)
{
    // The draw is one instance of six vertices (two triangles) per leaf: llvmpipe runs its
    // vertex pipeline once per instance, so millions of tiny instances would cost far more.
    uint i = atomicAdd(command.count, 6u) / 6u;
    vec2 a = corner(xy), b = corner(xy + ivec2(size.x, 0)), c = corner(xy + ivec2(0, size.y)), d = corner(xy + size);
    leaves[i].rect = uvec4(xy, size);
    leaves[i].corners = vec4(a.x, b.x, c.x, d.x);
    leaves[i].depths = vec4(a.y, b.y, c.y, d.y);
}

bool flat_enough(vec4 range, float cell)
{
    // NaN ranges compare false: such cells split down to pixels.
    float spread = (range.y - range.x) * u_scale;
    // A step shows as one second difference the size of the jump, whatever the cell size.
    float bend = range.z * u_scale * max(cell * cell / 8.0, 1.0);
    return spread <= u_threshold || bend <= u_threshold;
}

void main()
{
    ivec2 cell = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(cell, textureSize(u_level, 0).xy))) {
        return;
    }
    if (u_top == 0 && flat_enough(texelFetch(u_parent, ivec3(cell / 2, u_layer), 0), float(2 * u_cell))) {
        return;
    }
    ivec2 xy = cell * u_cell;
    if (flat_enough(texelFetch(u_level, ivec3(cell, u_layer), 0), float(u_cell))) {
        emit(xy, min(ivec2(u_cell), u_tile - xy));
    } else if (u_cell == 2) {
        // Depth edges are mostly crossed horizontally (disparity is horizontal): a column
        // whose two pixels agree stays one 1x2 quad, halving the leaves along edges.
        for (int x = 0; x < 2; x++) {
            ivec2 p = xy + ivec2(x, 0);
            if (p.x >= u_tile.x) {
                continue;
            }
            float lo = texelFetch(u_parallax, ivec3(p, u_layer), 0).r;
            bool tall = p.y + 1 < u_tile.y;
            float hi = tall ? texelFetch(u_parallax, ivec3(p + ivec2(0, 1), u_layer), 0).r : lo;
            if (tall && abs(hi - lo) * u_scale <= u_threshold) {
                emit(p, ivec2(1, 2));
            } else {
                emit(p, ivec2(1));
                if (tall) {
                    emit(p + ivec2(0, 1), ivec2(1));
                }
            }
        }
    }
}
