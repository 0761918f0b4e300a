#version 330 core
// One pixel of a rendered view, forward-splatted into a target view: moved by its own
// disparity (u_target - u_source)(s·p + f) in tile pixels and drawn as a one-pixel point at
// its own window depth, so the depth test keeps the nearest of the pixels landing together.
// Drawn with glDrawArrays(GL_POINTS, 0, w·h): the pixel is gl_VertexID.
uniform sampler2DArray u_color;
uniform sampler2DArray u_depth;
// The disparity record (parallax, recorded?) when the source has one (u_recorded).
uniform sampler2DArray u_record;
uniform int u_recorded;
uniform int u_layer;
uniform ivec2 u_tile;
uniform float u_du;
// (s, f) times half the tile width: pixels per unit of parallax, and of focus.
uniform vec2 u_px;
// (a_hi, a_lo, c/b): the parallax of synth_parallax.frag, computed here instead of read from
// its texture (one fetch fewer per point, and no full-tile pass per source).
uniform vec3 u_model;
// The comfort remap in tile pixels (off: z <= 0), applied to the outermost view's disparity
// (depth_remap.glsl is inserted after #version).
uniform vec4 u_remap;
// 1 when window depth is z_ndc (glClipControl GL_ZERO_TO_ONE), else 0.
uniform int u_zero_to_one;
flat out vec3 v_color;

void main()
{
    ivec2 src = ivec2(gl_VertexID % u_tile.x, gl_VertexID / u_tile.x);
    float depth = texelFetch(u_depth, ivec3(src, u_layer), 0).r;
    float q = ((2.0 * depth - 1.0) + u_model.x) + u_model.y;
    float p = 1.0 - u_model.z * q;
    vec2 rec = u_recorded == 1 ? texelFetch(u_record, ivec3(src, u_layer), 0).rg : vec2(0.0);
    if (rec.g > 0.5)
        p = rec.r;
    if (u_remap.z > 0.0 && u_px.x != 0.0)
        p = holoinject_remap(u_px.x * p, u_remap) / u_px.x;
    float x = float(src.x) + 0.5 + u_du * (u_px.x * p + u_px.y);
    vec2 pos = vec2(x, float(src.y) + 0.5) / vec2(u_tile) * 2.0 - 1.0;
    float z = u_zero_to_one == 1 ? depth : 2.0 * depth - 1.0;
    gl_Position = vec4(pos, z, 1.0);
    gl_PointSize = 1.0;
    v_color = texelFetch(u_color, ivec3(src, u_layer), 0).rgb;
}
