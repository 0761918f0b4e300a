#version 430 core
// The row warp: disparity is horizontal, so every row of a target view is made from the same
// row of its sources alone. One invocation owns one row of one target, so it can depth-test
// against its own writes without atomics. Each pair of neighbouring source pixels is a
// one-pixel-tall cell of Didyk et al.'s grid: where their disparities differ by no more than
// the threshold it is warped as one piece (colour and depth interpolated between the two
// centres, exact for planes); where they differ by more it is a depth edge, each pixel keeps
// its own half-pixel footprint, and a gap opening between them (a disocclusion) is filled with
// the farther of the two, pushed back so that anything actually seen there wins. The row is
// made as a merge of the source walk and the target walk in occlusion order (`scan`): each
// target pixel written once, without reading back, in lock-step across the rows a SIMD
// machine runs side by side.
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
// A source row is wider by the guard band on both sides (`u_guard` px, 0 without one). A scan
// walks the `guard` columns of it its target can see (`band_used`): its pixel i sits at target
// column i - guard.
uniform int u_guard;
int guard;
int src_width;
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

// The row's first scan writes every target pixel exactly once (`scan`), so it neither clears
// the row first nor reads anything back.
bool first_scan;

void put(int x, vec4 c, float z, bool hole)
{
    int i = out_base + x;
    if (first_scan) {
        out_pixels[i] = Out(packUnorm4x8(c), uintBitsToFloat(floatBitsToUint(z) | (hole ? HOLE : 0u)));
        return;
    }
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

// One source pixel as the scan holds it: where it lands (NaN, infinite or absurd positions,
// points at the camera, are not `ok`), its disparity, colour and depth.
struct Landed {
    float X;
    float d;
    uint color;
    float z;
    bool ok;
};

// Source pixel `i` of the scan; `dir` -1 mirrors the row, so that nearer pixels always move
// to the right of the scan (see `scan`).
Landed land(int base, int i, float k, float f, float dir)
{
    Pixel s = src_pixels[base + (dir > 0.0 ? i : src_width - 1 - i)];
    float d = dir * (k * s.parallax + f);
    float X = float(i - guard) + 0.5 + d;
    bool ok = abs(X) < 1.0e6;
    return Landed(ok ? X : -1.0e30, d, s.color, s.depth, ok);
}

// Target pixel `x` of the scan (mirrored like the sources) from the pair of source pixels
// around it, `a` (left, landed at or before its centre) and `b` (the first to land after
// it); `edge_a`/`edge_b`: the row ends there.
void emit(int x, Landed a, Landed b, bool edge_a, bool edge_b, float dir)
{
    float c = float(x) + 0.5;
    // How much of b the pixel takes (0: all a), and whether it is a fill over a hole; chosen
    // without branching into separate writes, which a SIMD machine would run one after another.
    float w;
    bool hole = false;
    if (edge_a || !a.ok || edge_b || !b.ok) {
        // Beyond the row's first or last landed pixel (or a position left out): that pixel
        // keeps its half-pixel footprint and stretches over what opens up past it.
        bool use_a = edge_b || !b.ok;
        w = use_a ? 0.0 : 1.0;
        float X = use_a ? a.X : b.X;
        hole = !(use_a ? a.ok : b.ok) || abs(c - X) >= 0.5;
    } else if (c >= b.X) {
        // b's own right half (a depth edge follows it): nearer than what it hides there.
        w = 1.0;
    } else if (abs(b.d - a.d) <= u_threshold) {
        w = clamp((c - a.X) / (b.X - a.X), 0.0, 1.0);
    } else if (c < a.X + 0.5) {
        w = 0.0;
    } else if (c >= b.X - 0.5) {
        w = 1.0;
    } else {
        // A disocclusion: the farther of the two, pushed back so that anything seen there wins.
        w = nearer(b.z, a.z) ? 0.0 : 1.0;
        hole = true;
    }
    vec4 col = mix(unpackUnorm4x8(a.color), unpackUnorm4x8(b.color), w);
    float z = mix(a.z, b.z, w);
    if (hole && !(edge_a || !a.ok || edge_b || !b.ok)) {
        z = clamp(z + u_far_bias, 0.0, 1.0);
    }
    put(dir > 0.0 ? x : width - 1 - x, col, z, hole);
}

// The target row from one source row as a merge of two sorted walks. Scanned in the
// direction nearer pixels move, the surface seen at a target centre c is the first source
// pixel b that lands beyond c (a nearer one landing there would have to come from further
// along the row, i.e. move against its own direction) together with the one before it, a;
// and b only ever moves forward as c does. So each step either takes the next source pixel
// or writes the next target pixel: about one of each per step, no loop within a step, no
// read of what was written: the lanes of a SIMD machine, each on its own row, stay in step
// (the walk it replaces branched per pixel and read back every write for its depth test).
// Cell (a, b), just passed by the scan, landed behind what was already written (up to the
// centre `c`), between the first and last stretches over holes [h0, h1] (centres): where it
// lands on a stretch, it is background the source saw, uncovered by a nearer piece that moved
// away over a gap, which first-hit order cannot reach; elsewhere what is there is nearer.
// Rare (cells hidden behind a nearer piece), so its read-back costs little.
void over_holes(Landed a, Landed b, bool cont, float c, float h0, float h1, float dir)
{
    float lo = cont ? min(a.X, b.X) : b.X - 0.5;
    float hi = cont ? max(a.X, b.X) : b.X + 0.5;
    int x0 = max(int(ceil(max(lo, h0) - 0.5)), 0);
    int x1 = min(int(ceil(min(hi, min(h1 + 0.5, c)) - 0.5)), width);
    bool was = first_scan;
    first_scan = false;
    for (int x = x0; x < x1; x++) {
        float w = cont ? clamp((float(x) + 0.5 - a.X) / (b.X - a.X), 0.0, 1.0) : 1.0;
        vec4 col = mix(unpackUnorm4x8(a.color), unpackUnorm4x8(b.color), w);
        put(dir > 0.0 ? x : width - 1 - x, col, mix(a.z, b.z, w), false);
    }
    first_scan = was;
}

// The target row from one source row as a merge of two sorted walks. Scanned in the
// direction nearer pixels move, the surface seen at a target centre c is the first source
// pixel b that lands beyond c (a nearer one landing there would have to come from further
// along the row, i.e. move against its own direction) together with the one before it, a;
// and b only ever moves forward as c does. So each step either takes the next source pixel
// or writes the next target pixel: about one of each per step, no loop within a step, no
// read of what was written: the lanes of a SIMD machine, each on its own row, stay in step
// (the walk it replaces branched per pixel and read back every write for its depth test).
// The one exception: where (a, b) is a gap, farther pixels from beyond the nearer piece may
// land in it; they replace the stretch when the scan passes them (`over_holes`).
void scan(int src, float du)
{
    float k = du * u_px.x, f = du * u_px.y;
    // Parallax grows with distance, so with k > 0 nearer pixels move left: mirror the row.
    float dir = k > 0.0 ? -1.0 : 1.0;
    // The band's columns this target can see: what moves in from beyond the edge at parallax
    // -1 to 1, and one more (as rows_cpu/row.rs `band_used`).
    guard = 0;
    if (u_guard > 0) {
        float reach = max(abs(f), max(abs(k + f), abs(f - k)));
        // All of it past its width, and for shifts not finite (int() of either is undefined,
        // and max() of a NaN either operand).
        bool small = abs(k) < 1.0e30 && abs(f) < 1.0e30 && reach < float(u_guard);
        guard = small ? min(int(ceil(reach)) + 1, u_guard) : u_guard;
    }
    src_width = width + 2 * guard;
    int base = (src * u_tile.y + row) * (width + 2 * u_guard) + (u_guard - guard);
    Landed a = land(base, 0, k, f, dir);
    Landed b = a;
    // The pixel after b: where (b, n) is a depth edge, b keeps its right half-pixel whatever
    // lands under it, so b is passed only once c is beyond X + 1/2 ("reach").
    Landed n = land(base, min(1, src_width - 1), k, f, dir);
    int t = 0;
    int x = 0;
    // Centres of the first and last stretched pixels written between two landed ones, and the
    // furthest any passed pixel landed: a cell behind it landed under what was already
    // written, where it can only replace stretches.
    float h0 = 1.0e30, h1 = -1.0e30;
    float front = -1.0e30;
    for (int step = 0; step < 2 * src_width + 2 && x < width; step++) {
        float c = float(x) + 0.5;
        bool edge_after = t + 1 >= src_width || !n.ok || abs(n.d - b.d) > u_threshold;
        float reach = b.X + (edge_after ? 0.5 : 0.0);
        if (t < src_width && reach <= c) {
            if (t > 0 && a.ok && b.ok && b.X < front - 0.5 && b.X + 0.5 > h0 && min(a.X, b.X) < h1 + 0.5) {
                over_holes(a, b, abs(b.d - a.d) <= u_threshold, c, h0, h1, dir);
            }
            front = max(front, b.X);
            a = b;
            b = n;
            t++;
            if (t + 1 < src_width) {
                n = land(base, t + 1, k, f, dir);
            }
            edge_after = t + 1 >= src_width || !n.ok || abs(n.d - b.d) > u_threshold;
            reach = b.X + (edge_after ? 0.5 : 0.0);
        }
        if (t >= src_width || reach > c) {
            bool gap = t > 0 && t < src_width && a.ok && b.ok && abs(b.d - a.d) > u_threshold
                && c >= a.X + 0.5 && c < b.X - 0.5;
            if (gap) {
                h0 = min(h0, c);
                h1 = c;
            }
            emit(x, a, b, t == 0, t >= src_width, dir);
            x++;
        }
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
    first_scan = true;
    Target t = targets[layer];
    bool two = t.src.z == 2;
    if (u_second_fills_holes == 1) {
        second = false;
        scan(t.src.y, t.du.y);
        first_scan = false;
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
            first_scan = false;
        }
        scan(t.src.y, t.du.y);
        row_done(false);
    }
}
