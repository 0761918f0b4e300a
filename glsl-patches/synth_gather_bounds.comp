#version 430 core
// One level of the per-row parallax bounds of a source (synth_gather.frag): texel i of level
// l is the (min, max) parallax of pixels [i·2^l, (i+1)·2^l) of its row, made from two texels
// of level l-1 (level 1 from the packed pixels). Levels lie side by side along x; the top
// one is a single texel per row: the whole row.
layout(local_size_x = 64) in;

uniform usampler2DArray u_packed;
layout(rg32f) uniform image2DArray u_bounds;
uniform int u_layer;
uniform int u_width;
uniform int u_rows;
// This level's offset and texel count, and the level below's (offset -1: the packed pixels).
uniform ivec2 u_this;
uniform ivec2 u_below;

vec2 below(int i, int y)
{
    if (u_below.x < 0) {
        float p = uintBitsToFloat(texelFetch(u_packed, ivec3(i, y, u_layer), 0).x);
        return vec2(p);
    }
    return imageLoad(u_bounds, ivec3(u_below.x + i, y, u_layer)).rg;
}

void main()
{
    int i = int(gl_GlobalInvocationID.x), y = int(gl_GlobalInvocationID.y);
    if (i >= u_this.y || y >= u_rows) {
        return;
    }
    vec2 m = below(2 * i, y);
    if (2 * i + 1 < u_below.y) {
        vec2 n = below(2 * i + 1, y);
        m = vec2(min(m.x, n.x), max(m.y, n.y));
    }
    imageStore(u_bounds, ivec3(u_this.x + i, y, u_layer), vec4(m, 0.0, 0.0));
}
