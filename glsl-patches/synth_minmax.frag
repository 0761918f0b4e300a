#version 330 core
// One level of the min/max parallax pyramid. A cell's range covers its pixels and one pixel
// around them: a grid vertex takes its parallax from the four pixels around it, so a cell
// whose own pixels are flat can still have corners on a depth edge next to it.
uniform sampler2DArray u_src;
uniform int u_layer;
// 1: from the per-pixel parallax (cells of 2x2 pixels), 0: from the level below.
uniform int u_first;
out vec2 o_range;

void main()
{
    ivec2 c = ivec2(gl_FragCoord.xy);
    ivec2 size = textureSize(u_src, 0).xy;
    vec2 r = vec2(3.0e38, -3.0e38);
    if (u_first == 1) {
        for (int y = -1; y <= 2; y++) {
            for (int x = -1; x <= 2; x++) {
                ivec2 p = clamp(2 * c + ivec2(x, y), ivec2(0), size - 1);
                float v = texelFetch(u_src, ivec3(p, u_layer), 0).r;
                r = vec2(min(r.x, v), max(r.y, v));
            }
        }
    } else {
        for (int y = 0; y <= 1; y++) {
            for (int x = 0; x <= 1; x++) {
                ivec2 p = min(2 * c + ivec2(x, y), size - 1);
                vec2 v = texelFetch(u_src, ivec3(p, u_layer), 0).rg;
                r = vec2(min(r.x, v.x), max(r.y, v.y));
            }
        }
    }
    o_range = r;
}
