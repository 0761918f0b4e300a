#version 430 core
// A source view's colour, window depth and parallax packed per pixel into storage, once per
// source, for the row warp to read (synth_rows.comp).
layout(local_size_x = 8, local_size_y = 8) in;

uniform sampler2DArray u_color;
uniform sampler2DArray u_depth;
uniform sampler2DArray u_parallax;
uniform int u_layer;
uniform ivec2 u_tile;
// The source's disparity record (parallax, recorded?) when it has one (u_recorded), and the
// scene's model (a_hi, a_lo, c/b, reversed) that turns a recorded parallax into the window
// depth the warp orders pixels by (synth_parallax.frag runs it the other way).
uniform sampler2DArray u_record;
uniform int u_recorded;
uniform vec4 u_model;

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
    float d = texelFetch(u_depth, q, 0).r;
    vec2 r = u_recorded == 1 ? texelFetch(u_record, q, 0).rg : vec2(0.0);
    if (r.g > 0.5 && u_model.z != 0.0) {
        float far = u_model.w > 0.5 ? 0.0 : 1.0;
        float z = (1.0 - r.r) / u_model.z - u_model.x - u_model.y;
        d = r.r >= 1.0 - 1e-6 ? far : clamp(z * 0.5 + 0.5, 0.0, 1.0);
    }
    src_pixels[i] = Pixel(packUnorm4x8(texelFetch(u_color, q, 0)), d, texelFetch(u_parallax, q, 0).r);
}
