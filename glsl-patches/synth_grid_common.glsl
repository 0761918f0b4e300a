// Shared by the grid's compute passes (inserted after their #version line): the leaf list,
// its draw command, the flatness test and the corner values a leaf carries.
uniform sampler2DArray u_parallax;
uniform sampler2DArray u_depth;
uniform int u_layer;
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

// A leaf at `xy` of `size` pixels, with corner values a (at xy), b (+x), c (+y), d (+x+y).
void emit_corners(ivec2 xy, ivec2 size, vec2 a, vec2 b, vec2 c, vec2 d)
{
    // Six vertices (two triangles) per leaf, one non-instanced draw: llvmpipe runs its
    // vertex pipeline once per instance, so millions of tiny instances would cost far more.
    uint i = atomicAdd(command.count, 6u) / 6u;
    leaves[i].rect = uvec4(xy, size);
    leaves[i].corners = vec4(a.x, b.x, c.x, d.x);
    leaves[i].depths = vec4(a.y, b.y, c.y, d.y);
}

void emit(ivec2 xy, ivec2 size)
{
    emit_corners(xy, size, corner(xy), corner(xy + ivec2(size.x, 0)), corner(xy + ivec2(0, size.y)), corner(xy + size));
}

bool flat_enough(vec4 range, float cell)
{
    // NaN ranges compare false: such cells split down to pixels.
    float spread = (range.y - range.x) * u_scale;
    // A step shows as one second difference the size of the jump, whatever the cell size.
    float bend = range.z * u_scale * max(cell * cell / 8.0, 1.0);
    return spread <= u_threshold || bend <= u_threshold;
}
