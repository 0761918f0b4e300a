#version 430 core
// A row-warped target into its tile: colour, and the warped depth (so that what the program
// draws after the warp point, such as a HUD, depth-tests against the view as it would).
// The warped pixels (colour, depth bits; a depth's sign bit marks a hole, synth_rows.comp)
// are read through a buffer texture over the row warp's storage: on llvmpipe a fragment
// shader's storage-buffer load costs several texel fetches.
uniform usamplerBuffer u_warped;
uniform int u_layer;
uniform ivec2 u_origin;
uniform ivec2 u_tile;
out vec4 o_color;

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy) - u_origin;
    uvec2 o = texelFetch(u_warped, (u_layer * u_tile.y + p.y) * u_tile.x + p.x).xy;
    o_color = unpackUnorm4x8(o.x);
    gl_FragDepth = abs(uintBitsToFloat(o.y));
}
