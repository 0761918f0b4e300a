#version 430 core
// The adaptive quad grid (Didyk et al. 2011): one dispatch per pyramid level, coarsest
// first. A cell is a leaf when its parallax range, in pixels of the outermost target view,
// is within the threshold and its parent's is not (ranges only shrink towards the leaves,
// so that parent was split). Cells of 2x2 pixels still too deep split into single pixels.
// Leaves are appended to a list that feeds one instanced draw per target view; each carries
// the parallax at its four corners (the farthest of the four pixels around each corner, so
// quads on a depth edge stretch across the disocclusion with the background).
layout(local_size_x = 8, local_size_y = 8) in;

uniform sampler2DArray u_parallax;
uniform sampler2DArray u_level;
uniform sampler2DArray u_parent;
uniform int u_layer;
uniform int u_cell;
uniform int u_top;
uniform float u_scale;
uniform float u_threshold;
uniform ivec2 u_tile;

struct Leaf {
    uvec4 rect;
    vec4 corners;
};
layout(std430, binding = 0) buffer Leaves { Leaf leaves[]; };
layout(std430, binding = 1) buffer Command { uint count; uint instances; uint first; uint base; } command;

float corner(ivec2 v)
{
    float p = -3.0e38;
    for (int y = -1; y <= 0; y++) {
        for (int x = -1; x <= 0; x++) {
            ivec2 q = clamp(v + ivec2(x, y), ivec2(0), u_tile - 1);
            p = max(p, texelFetch(u_parallax, ivec3(q, u_layer), 0).r);
        }
    }
    return p;
}

void emit(ivec2 xy, ivec2 size)
{
    uint i = atomicAdd(command.instances, 1u);
    leaves[i].rect = uvec4(xy, size);
    leaves[i].corners = vec4(corner(xy), corner(xy + ivec2(size.x, 0)), corner(xy + ivec2(0, size.y)), corner(xy + size));
}

bool flat_enough(vec2 range)
{
    // NaN ranges compare false: such cells split down to pixels.
    return (range.y - range.x) * u_scale <= u_threshold;
}

void main()
{
    ivec2 cell = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(cell, textureSize(u_level, 0).xy))) {
        return;
    }
    if (u_top == 0 && flat_enough(texelFetch(u_parent, ivec3(cell / 2, u_layer), 0).rg)) {
        return;
    }
    ivec2 xy = cell * u_cell;
    if (flat_enough(texelFetch(u_level, ivec3(cell, u_layer), 0).rg)) {
        emit(xy, min(ivec2(u_cell), u_tile - xy));
    } else if (u_cell == 2) {
        for (int y = 0; y < 2; y++) {
            for (int x = 0; x < 2; x++) {
                ivec2 p = xy + ivec2(x, y);
                if (all(lessThan(p, u_tile))) {
                    emit(p, ivec2(1));
                }
            }
        }
    }
}
