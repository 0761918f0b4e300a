#version 430 core
// The gather warp: each pixel of a synthesised view finds, in the same row of its source,
// what lands on it, so a view is one pass that writes every pixel once (DESIGN §5).
//
// A source pixel s with parallax p lands at X(s) = s + ½ + a·p + b. Views move sideways
// only, so a nearer surface moves further against the camera's motion: where two source
// pixels land on one target pixel, the one further in the direction of a's sign is nearer
// (a ≥ 0: the larger s). The pixel therefore walks the source row in that order from the
// furthest pixel that could land on it, and the first pixel that covers it wins, with no
// depth test. A min/max parallax hierarchy per row (synth_gather_bounds.comp) skips blocks
// of 2^l pixels that cannot land on it: a walk costs a few steps, not the disparity range.
//
// What a pixel covers is the row warp's rule (synth_rows.comp): neighbours whose
// disparities differ by at most the threshold are one piece, colour and depth interpolated
// between their landing points (exact for planes); at a larger step (a depth edge) each keeps
// half a pixel on its side, and the gap opening between them (a disocclusion) is filled with
// the farther of the two — the first pixel, walking the other way, that lands beyond this
// one — pushed back in depth so that anything drawn later tests as it would.
//
// Most pixels lie inside a piece whose source pixels are found directly: s = c - ½ - a·p - b
// with p the parallax under c, then once more with the parallax found (`quick`). Such a
// piece is what the walk would find when no pixel before it in walk order can land over it:
// each packed pixel carries how far a view may move before one can (synth_gather_reach.comp).
// Only the rest (depth edges, disocclusions, what that bound cannot vouch for) walk.
uniform usampler2DArray u_packed;
uniform sampler2DArray u_bounds;
// Levels of the bounds (the top one is one texel per row) and each level's x offset.
uniform int u_levels;
uniform int u_offset[16];
uniform int u_width;
uniform float u_threshold;
uniform float u_far_bias;
flat in vec4 v_ab;
flat in ivec3 v_src;
flat in ivec2 v_origin;
out vec4 o_color;

// Steps of a walk before it gives up (a pixel nothing lands on is then a hole).
const int MAX_STEPS = 96;

int y;

uvec4 pixel(int layer, int s)
{
    return texelFetch(u_packed, ivec3(s, y, layer), 0);
}

vec2 bounds(int layer, int l, int i)
{
    return texelFetch(u_bounds, ivec3(u_offset[l] + i, y, layer), 0).rg;
}

float parallax(uvec4 q)
{
    return uintBitsToFloat(q.x);
}

// Whether source pixel s covers the target pixel centred at c, and with what.
bool covers(int layer, int s, float c, float a, float b, out vec4 color, out float z)
{
    uvec4 q = pixel(layer, s);
    float p0 = parallax(q);
    float x0 = float(s) + 0.5 + a * p0 + b;
    color = unpackUnorm4x8(q.z);
    z = uintBitsToFloat(q.y);
    if (c < x0 - 0.5) {
        return false;
    }
    if (c < x0) {
        // Its left half, unless it is one piece with its left neighbour (whose piece covers it).
        return s == 0 || abs(a * (p0 - parallax(pixel(layer, s - 1)))) > u_threshold;
    }
    if (s + 1 < u_width) {
        uvec4 r = pixel(layer, s + 1);
        float p1 = parallax(r);
        if (abs(a * (p1 - p0)) <= u_threshold) {
            float x1 = float(s) + 1.5 + a * p1 + b;
            if (c >= x1) {
                return false;
            }
            float t = clamp((c - x0) / max(x1 - x0, 1.0e-6), 0.0, 1.0);
            color = mix(color, unpackUnorm4x8(r.z), t);
            z = mix(z, uintBitsToFloat(r.y), t);
            return true;
        }
    }
    return c < x0 + 0.5;
}

// The source pixel whose piece should hold c, if the parallax around it were p.
int aim(float p, float c, float a, float b)
{
    return clamp(int(floor(c - 0.5 - a * p - b)), 0, u_width - 2);
}

// 1: c lies inside the piece [s, s+1] and nothing before it in walk order can land over it
// (color and z set); 0: not inside it (s moved to the next guess); -1: the walk decides.
int piece(int layer, inout int s, float c, float a, float b, out vec4 color, out float z)
{
    uvec4 q0 = pixel(layer, s), q1 = pixel(layer, s + 1);
    float p0 = parallax(q0), p1 = parallax(q1);
    float x0 = float(s) + 0.5 + a * p0 + b;
    float x1 = float(s) + 1.5 + a * p1 + b;
    if (!(abs(a * (p1 - p0)) <= u_threshold)) {
        return -1;
    }
    if (c < x0 || c >= x1) {
        s = aim(c < x0 ? p0 : p1, c, a, b);
        return 0;
    }
    float safe = a >= 0.0 ? unpackHalf2x16(q1.w).x : unpackHalf2x16(q0.w).y;
    if (!(abs(a) <= safe)) {
        return -1;
    }
    float t = clamp((c - x0) / max(x1 - x0, 1.0e-6), 0.0, 1.0);
    color = mix(unpackUnorm4x8(q0.z), unpackUnorm4x8(q1.z), t);
    z = mix(uintBitsToFloat(q0.y), uintBitsToFloat(q1.y), t);
    return 1;
}

// The piece holding c found without a walk, when it can be trusted.
bool quick(int layer, float a, float b, float c, out vec4 color, out float z)
{
    if (u_width < 2) {
        return false;
    }
    int s = aim(parallax(pixel(layer, clamp(int(c), 0, u_width - 1))), c, a, b);
    for (int i = 0; i < 2; i++) {
        int r = piece(layer, s, c, a, b, color, z);
        if (r != 0) {
            return r == 1;
        }
    }
    return false;
}

// Whether block i of level l (pixels [i·2^l, (i+1)·2^l)) cannot land on c: all of it lands
// past c on one side or the other.
bool misses(int layer, int l, int i, float a, float b, float c)
{
    vec2 m = bounds(layer, l, i);
    float lo = min(a * m.x, a * m.y), hi = max(a * m.x, a * m.y);
    float b0 = float(i << l);
    return b0 + lo + b > c || b0 + float(1 << l) + 0.5 + u_threshold + hi + b <= c;
}

// The first pixel in walk order (dir = +1: from the right, the larger s nearer) that covers
// c. The walk is a hierarchical trace: at each step the block of level l containing s is
// skipped whole when it cannot land on c (and the next step tries a block twice as large),
// else the level drops; at level 0 the pixel itself is tested.
bool walk(int layer, float a, float b, float c, int dir, out vec4 color, out float z)
{
    vec2 row = bounds(layer, u_levels, 0);
    float lo_ap = min(a * row.x, a * row.y), hi_ap = max(a * row.x, a * row.y);
    // Pixels that can land on c: X(s) - ½ ≤ c and X(s) + 1 + threshold > c.
    int first = int(floor(c - lo_ap - b));
    int last = int(floor(c - 1.5 - u_threshold - hi_ap - b));
    int s = dir > 0 ? min(u_width - 1, first) : max(0, last);
    int end = dir > 0 ? max(0, last) : min(u_width - 1, first);
    int l = 1;
    for (int step = 0; step < MAX_STEPS; step++) {
        if (dir > 0 ? s < end : s > end) {
            return false;
        }
        if (l > 0) {
            int i = s >> l;
            if (misses(layer, l, i, a, b, c)) {
                s = dir > 0 ? (i << l) - 1 : (i + 1) << l;
                l = min(l + 1, u_levels);
            } else {
                l--;
            }
        } else {
            if (covers(layer, s, c, a, b, color, z)) {
                return true;
            }
            s -= dir;
            l = 1;
        }
    }
    return false;
}

// Whether no pixel of block i of level l lands entirely past c on the side dir points to.
bool short_of(int layer, int l, int i, float a, float b, float c, int dir)
{
    vec2 m = bounds(layer, l, i);
    float lo = min(a * m.x, a * m.y), hi = max(a * m.x, a * m.y);
    float b0 = float(i << l);
    return dir > 0 ? b0 + float(1 << l) - 1.0 + hi + b <= c : b0 + 1.0 + lo + b >= c;
}

// A disocclusion: nothing lands on c. It opened between a nearer pixel and a farther one,
// the farther on the side a's sign points to; that one is the first pixel, walking from the
// other side, whose footprint lies entirely past c (the same trace as `walk`).
void hole(int layer, float a, float b, float c, int dir, out vec4 color, out float z)
{
    vec2 row = bounds(layer, u_levels, 0);
    float lo_ap = min(a * row.x, a * row.y), hi_ap = max(a * row.x, a * row.y);
    int s = dir > 0 ? max(0, int(floor(c - hi_ap - b))) : min(u_width - 1, int(floor(c - 1.0 - lo_ap - b)) + 1);
    int found = dir > 0 ? u_width - 1 : 0;
    int l = 1;
    for (int step = 0; step < MAX_STEPS; step++) {
        if (s < 0 || s >= u_width) {
            break;
        }
        if (l > 0) {
            int i = s >> l;
            if (short_of(layer, l, i, a, b, c, dir)) {
                s = dir > 0 ? (i + 1) << l : (i << l) - 1;
                l = min(l + 1, u_levels);
            } else {
                l--;
            }
        } else {
            float x = float(s) + 0.5 + a * parallax(pixel(layer, s)) + b;
            if (dir > 0 ? x - 0.5 > c : x + 0.5 < c) {
                found = s;
                break;
            }
            s += dir > 0 ? 1 : -1;
            l = 1;
        }
    }
    uvec4 q = pixel(layer, found);
    color = unpackUnorm4x8(q.z);
    z = clamp(uintBitsToFloat(q.y) + u_far_bias, 0.0, 1.0);
}

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy) - v_origin;
    y = p.y;
    float c = float(p.x) + 0.5;
    vec4 color;
    float z;
    int dir = v_ab.x >= 0.0 ? 1 : -1;
    if (quick(v_src.x, v_ab.x, v_ab.y, c, color, z)) {
        o_color = color;
        gl_FragDepth = z;
        return;
    }
    if (!walk(v_src.x, v_ab.x, v_ab.y, c, dir, color, z)) {
        int dir2 = v_ab.z >= 0.0 ? 1 : -1;
        if (v_src.z < 2 || !walk(v_src.y, v_ab.z, v_ab.w, c, dir2, color, z)) {
            hole(v_src.x, v_ab.x, v_ab.y, c, dir, color, z);
        }
    }
    o_color = color;
    gl_FragDepth = z;
}
