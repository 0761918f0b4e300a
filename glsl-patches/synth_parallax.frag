#version 330 core
// Parallax p = 1 - c/w of each pixel of a rendered view, from its window depth (see
// src/synth/disparity.rs for why q is formed before the multiplication).
uniform sampler2DArray u_depth;
// The disparity record (parallax, recorded?) of this source, when it has one (u_recorded): a
// recorded pixel carries the parallax its draw was shifted by (before the remap, as a
// depth's).
uniform sampler2DArray u_record;
uniform int u_recorded;
uniform int u_layer;
// (a_hi, a_lo, c/b, unused)
uniform vec4 u_model;
// The comfort remap in tile pixels (off: z <= 0) and the outermost view's pixels per unit of
// parallax: the parallax written is R(S·p)/S, so every warp moves pixels by the remapped
// disparity (depth_remap.glsl is inserted after #version).
uniform vec4 u_remap;
uniform float u_px_per_parallax;
out float o_parallax;

void main()
{
    float d = texelFetch(u_depth, ivec3(ivec2(gl_FragCoord.xy), u_layer), 0).r;
    float z = 2.0 * d - 1.0;
    float q = (z + u_model.x) + u_model.y;
    float p = 1.0 - u_model.z * q;
    vec2 r = u_recorded == 1 ? texelFetch(u_record, ivec3(ivec2(gl_FragCoord.xy), u_layer), 0).rg : vec2(0.0);
    if (r.g > 0.5)
        p = r.r;
    float k = u_px_per_parallax;
    o_parallax = u_remap.z > 0.0 && k != 0.0 ? holoinject_remap(k * p, u_remap) / k : p;
}
