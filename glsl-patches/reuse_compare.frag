#version 330 core
// --reuse: one view's tile this frame against its kept render (multiview/history.rs). Equal
// pixels are discarded, so an occlusion query around the pass counts the pixels that differ.
// Drawn over a tile-sized viewport at the origin; u_origin is the tile's first texel in both
// textures (which are stored alike). The order of pixels within the tile does not matter.

uniform sampler2D u_now;
uniform sampler2D u_kept;
uniform ivec2 u_origin;

void main()
{
    ivec2 p = u_origin + ivec2(gl_FragCoord.xy);
    if (texelFetch(u_now, p, 0) == texelFetch(u_kept, p, 0))
        discard;
}
