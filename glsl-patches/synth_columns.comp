#version 430 core
// The grid's finest level: pixels whose 2x2 cell is still too deep (depth edges, mostly)
// become one-pixel-wide columns, as tall as the parallax along both of their vertical edges
// stays a straight line within the threshold. Disparity is horizontal, so a column never
// straddles a vertical depth edge, and along such an edge (the sides of anything upright)
// one column replaces a leaf per pixel. Each invocation walks one column of a segment.
layout(local_size_x = 64) in;

// Level 0 of the pyramid: cells of 2x2 pixels.
uniform sampler2DArray u_level;

const int SEGMENT = 32;

bool fine(int x, int y)
{
    return !flat_enough(texelFetch(u_level, ivec3(x / 2, y / 2, u_layer), 0), 2.0);
}

// Whether the vertex values v[s..t] lie on the line from v[s] to v[t], within the threshold.
bool straight(float v[SEGMENT + 1], int s, int t)
{
    for (int k = s + 1; k < t; k++) {
        float line = mix(v[s], v[t], float(k - s) / float(t - s));
        if (!(abs(v[k] - line) * u_scale <= u_threshold)) {
            return false;
        }
    }
    return true;
}

void main()
{
    int x = int(gl_GlobalInvocationID.x);
    int y0 = int(gl_GlobalInvocationID.y) * SEGMENT;
    if (x >= u_tile.x || y0 >= u_tile.y) {
        return;
    }
    int n = min(SEGMENT, u_tile.y - y0);
    // Corner values along the column's left and right edges, vertex rows y0 .. y0 + n.
    vec2 left[SEGMENT + 1], right[SEGMENT + 1];
    float pl[SEGMENT + 1], pr[SEGMENT + 1];
    bool any_fine = false;
    for (int k = 0; k < n && !any_fine; k++) {
        any_fine = fine(x, y0 + k);
    }
    if (!any_fine) {
        return;
    }
    for (int k = 0; k <= n; k++) {
        left[k] = corner(ivec2(x, y0 + k));
        right[k] = corner(ivec2(x + 1, y0 + k));
        pl[k] = left[k].x;
        pr[k] = right[k].x;
    }
    int k = 0;
    while (k < n) {
        if (!fine(x, y0 + k)) {
            k++;
            continue;
        }
        int e = k + 1;
        while (e < n && fine(x, y0 + e) && straight(pl, k, e + 1) && straight(pr, k, e + 1)) {
            e++;
        }
        emit_corners(ivec2(x, y0 + k), ivec2(1, e - k), left[k], right[k], left[e], right[e]);
        k = e;
    }
}
