#version 430 core
// A source view's colour, window depth and parallax packed per pixel into storage, once per
// source, for the row warp to read (synth_rows.comp).
layout(local_size_x = 8, local_size_y = 8) in;

uniform sampler2DArray u_color;
uniform sampler2DArray u_depth;
uniform sampler2DArray u_parallax;
uniform int u_layer;
uniform ivec2 u_tile;

struct Pixel {
    uint color;
    float depth;
    float parallax;
};
layout(std430, binding = 1) writeonly buffer Sources { Pixel src_pixels[]; };

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, u_tile))) {
        return;
    }
    ivec3 q = ivec3(p, u_layer);
    int i = (u_layer * u_tile.y + p.y) * u_tile.x + p.x;
    src_pixels[i] = Pixel(packUnorm4x8(texelFetch(u_color, q, 0)), texelFetch(u_depth, q, 0).r,
                          texelFetch(u_parallax, q, 0).r);
}
