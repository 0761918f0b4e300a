#version 330 core
// --reuse following the camera (synth/reproject.rs): the reprojected kept view over the
// synthesised one, in the target tile. A kept pixel is taken where it was splatted and its
// eye distance agrees with the synthesised pixel's within u_tolerance (relative): the same
// static surface, exact from the view's own render. Elsewhere (cracks, what came into view,
// moving objects, anything that now hides it) the synthesised pixel stays: dropped, not
// smeared. Drawn with fullscreen.vert over the tile's viewport.
uniform sampler2D u_kept;
uniform sampler2D u_kept_depth;
uniform sampler2D u_synth_depth;
uniform ivec2 u_rect_origin;
uniform vec2 u_model;
uniform int u_zero_to_one;
uniform float u_tolerance;
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
    if (isinf(ws) || !(abs(wk - ws) <= u_tolerance * ws))
        discard;
    o_color = vec4(kept.rgb, 1.0);
    gl_FragDepth = d;
}
