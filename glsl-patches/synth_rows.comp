#version 430 core
// The row warp: disparity is horizontal, so every row of a target view is made from the same
// row of its sources alone. One invocation owns one row of one target, so it can depth-test
// against its own writes without atomics. Each pair of neighbouring source pixels is a
// one-pixel-tall cell of Didyk et al.'s grid: where their disparities differ by no more than
// the threshold it is warped as one piece (colour and depth interpolated between the two
// centres, exact for planes); where they differ by more it is a depth edge, each pixel keeps
// its own half-pixel footprint, and a gap opening between them (a disocclusion) is filled with
// the farther of the two, pushed back so that anything actually seen there wins.
layout(local_size_x = 32) in;

// Sources and targets as plain storage (llvmpipe's loads and stores cost a fraction of its
// texel fetches and image accesses): per pixel, packed RGBA8, window depth and parallax.
struct Pixel {
    uint color;
    float depth;
    float parallax;
};
layout(std430, binding = 1) readonly buffer Sources { Pixel src_pixels[]; };
// A depth whose sign bit is set (depths are never negative) marks a pixel filled because
// nothing of the sources landed there (a disocclusion, what comes into view beyond the edge,
// or nothing at all yet): `count_holes` counts the ones that stay, and --reuse's kept
// views may replace them (reuse_reproject.frag reads the same bit).
struct Out {
    uint color;
    float depth;
};
layout(std430, binding = 2) buffer Targets_out { Out out_pixels[]; };
// The pixels left filled over holes, counted per row here when asked (a frame measured
// against exact: another walk over the row); a per-pixel atomic in the resolve pass cost a
// software rasteriser more than the resolve itself.
layout(std430, binding = 3) buffer Holes { uint holes; };
uniform int u_count_holes;
uniform ivec2 u_tile;
uniform int u_targets;
// (s, f) times half the tile width: pixels per unit of parallax, and of focus.
uniform vec2 u_px;
uniform float u_threshold;
// 1 under reversed-Z (nearer is larger).
uniform int u_reversed;
// Window depth towards the far side for disocclusion fill (negative under reversed-Z).
uniform float u_far_bias;

struct Target {
    // Source camera offsets u_target - u_source: second source, then the preferred one.
    vec4 du;
    // Source layers (second, preferred) and how many sources (1 or 2).
    ivec4 src;
};
layout(std430, binding = 0) readonly buffer Targets { Target targets[]; };

int row;
int width;
// Index of this row's first pixel in the output.
int out_base;

bool nearer(float a, float b)
{
    return u_reversed == 1 ? a >= b : a <= b;
}

// 1: a target's second source only fills what its preferred (nearer) source left as holes,
// so the two are never mixed on one surface (a depth test between two sources' samples of one
// surface picks either by a hair, in streaks: hybrid's views beside a rendered one were worse
// than synth's). 0 under --reuse, whose kept views fill those holes better than a far
// source does (measured: the rule took --reuse-motion's gain away).
uniform int u_second_fills_holes;
// Scanning the second source; its solid writes carry bit 30 (never set in a depth in [0, 1])
// until `row_done` clears it, so that its own pixels still depth-test against each other.
bool second;
const uint HOLE = 0x80000000u;
const uint SECOND = 0x40000000u;

void put(int x, vec4 c, float z, bool hole)
{
    int i = out_base + x;
    uint e = floatBitsToUint(out_pixels[i].depth);
    float was = uintBitsToFloat(e & ~(HOLE | SECOND));
    bool write;
    if (!second) {
        write = nearer(z, was);
    } else if ((e & HOLE) != 0u) {
        write = !hole || nearer(z, was);
    } else {
        write = (e & SECOND) != 0u && !hole && nearer(z, was);
    }
    if (write) {
        uint mark = hole ? HOLE : (second ? SECOND : 0u);
        out_pixels[i].depth = uintBitsToFloat(floatBitsToUint(z) | mark);
        out_pixels[i].color = packUnorm4x8(c);
    }
}

// The second source's marks cleared (its solid pixels are solid pixels), and the row's
// holes counted into the frame's when asked.
void row_done(bool marked)
{
    if (!marked && u_count_holes == 0) {
        return;
    }
    uint n = 0u;
    for (int x = 0; x < width; x++) {
        uint e = floatBitsToUint(out_pixels[out_base + x].depth);
        if ((e & SECOND) != 0u) {
            out_pixels[out_base + x].depth = uintBitsToFloat(e & ~SECOND);
        }
        n += e >> 31;
    }
    if (n != 0u && u_count_holes == 1) {
        atomicAdd(holes, n);
    }
}

// Target pixels whose centres lie in [a, b), clamped to the row.
ivec2 covered(float a, float b)
{
    return ivec2(max(int(ceil(a - 0.5)), 0), min(int(ceil(b - 0.5)), width));
}

// The span [a, b) filled with one colour and depth; `hole`: it is a stretch over a hole.
void fill(float a, float b, vec4 c, float z, bool hole)
{
    ivec2 r = covered(a, b);
    for (int i = r.x; i < r.y; i++) {
        put(i, c, z, hole);
    }
}

void scan(int src, float du)
{
    float k = du * u_px.x, f = du * u_px.y;
    float px = 0.0, pz = 0.0, pd = 0.0;
    vec4 pc = vec4(0.0);
    bool have = false;
    int base = (src * u_tile.y + row) * width;
    for (int x = 0; x < width; x++) {
        Pixel s = src_pixels[base + x];
        float d = k * s.parallax + f;
        float X = float(x) + 0.5 + d;
        // NaN, infinite or absurd positions (points at the camera) are left out.
        if (!(abs(X) < 1.0e6)) {
            have = false;
            continue;
        }
        vec4 c = unpackUnorm4x8(s.color);
        float z = s.depth;
        if (x == 0) {
            // The border pixel also covers whatever opens up beyond the view's edge.
            fill(-1.0e6, X - 0.5, c, z, true);
            fill(X - 0.5, X, c, z, false);
        } else if (!have) {
            fill(X - 0.5, X, c, z, false);
        } else if (abs(d - pd) <= u_threshold) {
            ivec2 r = covered(min(px, X), max(px, X));
            float inv = 1.0 / (X - px);
            for (int i = r.x; i < r.y; i++) {
                float t = clamp((float(i) + 0.5 - px) * inv, 0.0, 1.0);
                put(i, mix(pc, c, t), mix(pz, z, t), false);
            }
        } else {
            fill(px, px + 0.5, pc, pz, false);
            fill(X - 0.5, X, c, z, false);
            if (X - px > 1.0) {
                bool back = nearer(z, pz);
                fill(px + 0.5, X - 0.5, back ? pc : c, clamp((back ? pz : z) + u_far_bias, 0.0, 1.0), true);
            }
        }
        if (x == width - 1) {
            fill(X, X + 0.5, c, z, false);
            fill(X + 0.5, 1.0e6, c, z, true);
        }
        px = X;
        pz = z;
        pd = d;
        pc = c;
        have = true;
    }
}

void main()
{
    row = int(gl_GlobalInvocationID.x);
    int layer = int(gl_GlobalInvocationID.y);
    width = u_tile.x;
    if (row >= u_tile.y || layer >= u_targets) {
        return;
    }
    out_base = (layer * u_tile.y + row) * width;
    // Nothing landed yet: the far plane, marked as a hole.
    float far = uintBitsToFloat(floatBitsToUint(u_reversed == 1 ? 0.0 : 1.0) | 0x80000000u);
    for (int x = 0; x < width; x++) {
        out_pixels[out_base + x] = Out(0u, far);
    }
    Target t = targets[layer];
    bool two = t.src.z == 2;
    if (u_second_fills_holes == 1) {
        second = false;
        scan(t.src.y, t.du.y);
        second = two;
        if (two) {
            scan(t.src.x, t.du.x);
        }
        row_done(two);
    } else {
        // Both depth-tested alike: nearer wins whichever source it came from.
        second = false;
        if (two) {
            scan(t.src.x, t.du.x);
        }
        scan(t.src.y, t.du.y);
        row_done(false);
    }
}
