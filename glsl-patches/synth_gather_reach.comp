#version 430 core
// What the gather warp's quick path (synth_gather.frag) needs to trust a pixel it found
// directly: how far a view may move before any other pixel of the row can land over this
// one. The packed pixels are copied with it in their fourth word, once per source.
//
// Pixel t lands at X(t) = t + ½ + a·p(t) + b. For a > 0 the pixels that could cover what t
// covers lie to its right (the walk's order: the larger s is nearer); none does while for
// every j ≥ 1, X(t+j) - ½ ≥ X(t), that is a·(p(t) - p(t+j)) ≤ j - ½. So t is safe up to
//     A+(t) = min over j ≥ 1 with p(t+j) < p(t) of (j - ½) / (p(t) - p(t+j)),
// and A-(t) the same to the left for a < 0. Pixels farther than the row's parallax range
// allows (|a|·(p(t) - min p) + ½ for the largest |a| of the source's views) cannot matter;
// beyond MAX_SCAN pixels the row's minimum bounds the rest.
layout(local_size_x = 64) in;

uniform usampler2DArray u_staged;
uniform sampler2DArray u_bounds;
uniform int u_layer;
uniform ivec2 u_tile;
// x offset of the bounds' top level (one texel per row: the row's min and max parallax).
uniform int u_top;
// The largest |a| among the views warped from this source.
uniform float u_reach;
layout(rgba32ui) uniform writeonly uimage2DArray u_packed;

const int MAX_SCAN = 64;
// Stored reaches are shrunk by a little more than half precision rounds, so they stay safe.
const float SHRINK = 0.998;
const float NONE = 60000.0;

int y;

float parallax_at(int x)
{
    return uintBitsToFloat(texelFetch(u_staged, ivec3(x, y, u_layer), 0).x);
}

float reach(int t, float pt, int dir, float pmin)
{
    float drop = pt - pmin;
    if (!(drop > 0.0)) {
        return NONE;
    }
    int need = int(ceil(min(u_reach * drop + 0.5, 1.0e6)));
    int scan = min(need, MAX_SCAN);
    float r = scan < need ? (float(scan) + 0.5) / drop : NONE;
    for (int j = 1; j <= scan; j++) {
        int x = t + dir * j;
        if (x < 0 || x >= u_tile.x) {
            break;
        }
        float d = pt - parallax_at(x);
        if (d > 0.0) {
            r = min(r, (float(j) - 0.5) / d);
        }
    }
    return min(r * SHRINK, NONE);
}

void main()
{
    int t = int(gl_GlobalInvocationID.x);
    y = int(gl_GlobalInvocationID.y);
    if (t >= u_tile.x || y >= u_tile.y) {
        return;
    }
    uvec4 q = texelFetch(u_staged, ivec3(t, y, u_layer), 0);
    float pt = uintBitsToFloat(q.x);
    float pmin = texelFetch(u_bounds, ivec3(u_top, y, u_layer), 0).r;
    q.w = packHalf2x16(vec2(reach(t, pt, 1, pmin), reach(t, pt, -1, pmin)));
    imageStore(u_packed, ivec3(t, y, u_layer), q);
}
