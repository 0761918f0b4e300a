#version 430 core
// --reuse following the camera (synth/reproject.rs): a view's kept render, rendered a few
// frames ago with the camera elsewhere, fetched into the disocclusions of this frame's
// synthesised view, in its tile. Drawn with fullscreen.vert over the tile's viewport.
//
// The synthesised view is right wherever the rendered views saw the surface (moving objects
// included); where they did not it is a guess, a stretch of the farther side over the hole,
// which the row warp marks. There the stretch's depth says where the background is; moved
// back by the camera's motion (u_back · (clip - u_offset)) it lands on a pixel of the kept
// render. That pixel is taken when its own eye distance agrees with the moved point's within
// u_tolerance (relative): the same static surface, seen then. Anything else there (something
// nearer, an object that has moved since, nothing at all beyond the tile) leaves the
// synthesised pixel: dropped, not smeared. Outside holes the synthesised pixel stays too.
uniform sampler2D u_kept;
uniform sampler2D u_kept_depth;
uniform sampler2D u_synth_depth;
// The kept tile's first texel, and whether its rows are stored top-down.
uniform ivec2 u_origin;
uniform int u_flip;
uniform ivec2 u_rect_origin;
uniform ivec2 u_tile;
// Clip coordinates now -> then: the inverse of the kept view's motion (camera::ViewRig::
// clip_motion), made in f64 on the CPU.
uniform mat4 u_back;
uniform vec4 u_offset;
// (a, b) of the depth model z_ndc = -a + b/w.
uniform vec2 u_model;
uniform int u_zero_to_one;
uniform float u_tolerance;
// The row warp's output (synth_rows.comp); this target's is layer u_layer. A depth with its
// sign bit set is a pixel filled over a hole.
struct Out {
    uint color;
    float depth;
};
layout(std430, binding = 4) readonly buffer Warped { Out warped[]; };
uniform int u_layer;
out vec4 o_color;

float ndc_z(float d)
{
    return u_zero_to_one == 1 ? d : 2.0 * d - 1.0;
}

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy) - u_rect_origin;
    if ((floatBitsToUint(warped[(u_layer * u_tile.y + p.y) * u_tile.x + p.x].depth) & 0x80000000u) == 0u)
        discard;
    float z = ndc_z(texelFetch(u_synth_depth, p, 0).r);
    float w = u_model.y / (z + u_model.x);
    if (isinf(w) || !(w > 0.0))
        discard;
    vec2 ndc = (vec2(p) + 0.5) / vec2(u_tile) * 2.0 - 1.0;
    vec4 then = u_back * (vec4(ndc * w, z * w, w) - u_offset);
    if (!(then.w > 0.0))
        discard;
    vec2 at = floor((then.xy / then.w * 0.5 + 0.5) * vec2(u_tile));
    if (any(lessThan(at, vec2(0.0))) || any(greaterThanEqual(at, vec2(u_tile))))
        discard;
    ivec2 q = ivec2(at);
    ivec2 t = u_origin + ivec2(q.x, u_flip == 1 ? u_tile.y - 1 - q.y : q.y);
    float wk = u_model.y / (ndc_z(texelFetch(u_kept_depth, t, 0).r) + u_model.x);
    if (isinf(wk) || !(abs(wk - then.w) <= u_tolerance * then.w))
        discard;
    o_color = vec4(texelFetch(u_kept, t, 0).rgb, 1.0);
}
