#version 430 core
// A row-warped target into its tile: colour, and the warped depth (so that what the program
// draws after the warp point, such as a HUD, depth-tests against the view as it would).
struct Out {
    uint color;
    float depth;
};
layout(std430, binding = 2) readonly buffer Targets_out { Out out_pixels[]; };
// The pixels that stay filled over holes (their depth's sign bit: synth_rows.comp).
layout(std430, binding = 3) buffer Holes { uint holes; };
uniform int u_layer;
uniform ivec2 u_origin;
uniform ivec2 u_tile;
out vec4 o_color;

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy) - u_origin;
    Out o = out_pixels[(u_layer * u_tile.y + p.y) * u_tile.x + p.x];
    o_color = unpackUnorm4x8(o.color);
    gl_FragDepth = abs(o.depth);
    if ((floatBitsToUint(o.depth) & 0x80000000u) != 0u) {
        atomicAdd(holes, 1u);
    }
}
