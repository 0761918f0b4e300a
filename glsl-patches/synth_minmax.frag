#version 330 core
// One level of the parallax pyramid: per cell, the min and max parallax and a bound on its
// second differences. A cell's footprint covers its pixels and one pixel around them: a
// grid vertex takes its parallax from the four pixels around it, so a cell whose own pixels
// are smooth can still have corners on a depth edge next to it.
//
// The second differences matter because parallax p = 1 - c/w is affine in 1/w, and 1/w is
// affine in screen space over any plane: a planar surface warps exactly with one quad, however
// deep it is. What a quad cannot follow is curvature and depth edges (huge second
// differences), so cells split where those are, not merely where the depth range is large.
uniform sampler2DArray u_src;
uniform int u_layer;
// 1: from the per-pixel parallax (cells of 2x2 pixels), 0: from the level below.
uniform int u_first;
// (min, max, second-difference bound, unused)
out vec4 o_range;

void main()
{
    ivec2 c = ivec2(gl_FragCoord.xy);
    ivec2 size = textureSize(u_src, 0).xy;
    vec4 r = vec4(3.0e38, -3.0e38, 0.0, 0.0);
    if (u_first == 1) {
        float v[16];
        for (int y = 0; y < 4; y++) {
            for (int x = 0; x < 4; x++) {
                ivec2 p = clamp(2 * c + ivec2(x - 1, y - 1), ivec2(0), size - 1);
                float s = texelFetch(u_src, ivec3(p, u_layer), 0).r;
                v[y * 4 + x] = s;
                r.xy = vec2(min(r.x, s), max(r.y, s));
            }
        }
        float dxx = 0.0, dyy = 0.0, dxy = 0.0;
        for (int i = 0; i < 4; i++) {
            for (int k = 1; k < 3; k++) {
                dxx = max(dxx, abs(v[i * 4 + k - 1] - 2.0 * v[i * 4 + k] + v[i * 4 + k + 1]));
                dyy = max(dyy, abs(v[(k - 1) * 4 + i] - 2.0 * v[k * 4 + i] + v[(k + 1) * 4 + i]));
            }
        }
        for (int y = 0; y < 3; y++) {
            for (int x = 0; x < 3; x++) {
                dxy = max(dxy, abs(v[y * 4 + x] - v[y * 4 + x + 1] - v[(y + 1) * 4 + x] + v[(y + 1) * 4 + x + 1]));
            }
        }
        r.z = dxx + dyy + 2.0 * dxy;
    } else {
        for (int y = 0; y <= 1; y++) {
            for (int x = 0; x <= 1; x++) {
                ivec2 p = min(2 * c + ivec2(x, y), size - 1);
                vec4 s = texelFetch(u_src, ivec3(p, u_layer), 0);
                r.xyz = vec3(min(r.x, s.x), max(r.y, s.y), max(r.z, s.z));
            }
        }
    }
    o_range = r;
}
