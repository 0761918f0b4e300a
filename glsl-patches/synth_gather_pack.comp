#version 430 core
// A source view packed per pixel for the gather warp (synth_gather.frag), once per source:
// (parallax, window depth, colour as RGBA8) as integers, so one fetch gives all three. Also
// the first level of the per-row parallax bounds (pairs of pixels: min, max).
layout(local_size_x = 8, local_size_y = 8) in;

uniform sampler2DArray u_color;
uniform sampler2DArray u_depth;
uniform sampler2DArray u_parallax;
uniform int u_layer;
uniform ivec2 u_tile;
layout(rgba32ui) uniform writeonly uimage2DArray u_packed;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, u_tile))) {
        return;
    }
    ivec3 q = ivec3(p, u_layer);
    uvec4 v = uvec4(floatBitsToUint(texelFetch(u_parallax, q, 0).r), floatBitsToUint(texelFetch(u_depth, q, 0).r),
                    packUnorm4x8(texelFetch(u_color, q, 0)), 0u);
    imageStore(u_packed, q, v);
}
