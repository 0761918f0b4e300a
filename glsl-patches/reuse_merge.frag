#version 430 core
// --reuse following the camera (synth/reproject.rs): the reprojected kept view over the
// synthesised one, in the target tile. The synthesised view is right wherever the rendered
// views saw the surface (moving objects included); where they did not it is a guess, a
// stretch of the farther side over the hole, which the row warp marks. There a kept pixel,
// exact from the view's own render, is taken when it was splatted and its eye distance
// agrees with the stretch's within u_tolerance (relative): the same static background,
// seen. Elsewhere (cracks, what came into view, an object that moved, which is nearer or
// farther than the background it left) the synthesised pixel stays: dropped, not smeared.
// Outside holes the synthesised pixel stays too: measured, the kept view resampled through
// one-pixel points is less accurate there than the warp (README "--reuse").
// Drawn with fullscreen.vert over the tile's viewport.
uniform sampler2D u_kept;
uniform sampler2D u_kept_depth;
uniform sampler2D u_synth_depth;
uniform ivec2 u_rect_origin;
uniform vec2 u_model;
uniform int u_zero_to_one;
uniform float u_tolerance;
// The row warp's hole marks (synth_rows.comp); this target's are layer u_layer.
layout(std430, binding = 4) readonly buffer Marks { uint marks[]; };
uniform int u_layer;
uniform ivec2 u_tile;
out vec4 o_color;

float eye(float d)
{
    float z = u_zero_to_one == 1 ? d : 2.0 * d - 1.0;
    return u_model.y / (z + u_model.x);
}

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy) - u_rect_origin;
    vec4 kept = texelFetch(u_kept, p, 0);
    if (kept.a < 0.5)
        discard;
    float d = texelFetch(u_kept_depth, p, 0).r;
    float wk = eye(d);
    float ws = eye(texelFetch(u_synth_depth, p, 0).r);
    bool hole = marks[(u_layer * u_tile.y + p.y) * u_tile.x + p.x] == 1u;
    if (!hole || isinf(ws) || !(abs(wk - ws) <= u_tolerance * ws))
        discard;
    o_color = vec4(kept.rgb, 1.0);
    gl_FragDepth = d;
}
