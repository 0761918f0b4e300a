// holoinject: per-view clip-space camera shift (DESIGN.md section 3).
// holoinject_comfort = the remap R's (F, B, D_F, D_B) in units of parallax 1 - c/w, zero when
// off (holoinject_remap is depth_remap.glsl, prepended by the layer).
// holoinject_view = (k, c, h, mode); mode 0 perspective (infinite far plane or depth
// unknown), 1 orthographic, 2 unknown projection (w == 1 means orthographic), 3 perspective
// with reversed-Z, 4 perspective with a finite far plane.
// Valid GLSL 1.10 .. 4.60 and ES 1.00 .. 3.20: no const initialisers, no f suffixes,
// precision only under GL_ES (an app's `precision mediump float;` must not reach the shift).
uniform HOLOINJECT_HIGHP vec4 holoinject_view;
uniform HOLOINJECT_HIGHP vec4 holoinject_comfort;
HOLOINJECT_HIGHP vec4 holoinject_shift(HOLOINJECT_HIGHP vec4 holoinject_p)
{
    HOLOINJECT_HIGHP float holoinject_mode = holoinject_view.w;
    // The centre view must be bit-identical to the app's own rendering (also -0.0 and inf).
    if (holoinject_view.x == 0.0 && holoinject_view.z == 0.0)
        return holoinject_p;
    if (holoinject_mode == 1.0 || (holoinject_mode == 2.0 && holoinject_p.w == 1.0))
        return holoinject_p;
    HOLOINJECT_HIGHP float holoinject_far_z = holoinject_mode == 3.0 ? 0.0 : holoinject_p.w;
    // Far-plane vertices (.xyww skyboxes) are at infinity: no convergence term. Only an
    // infinite (or unknown) projection puts them a few ulps off the plane.
    HOLOINJECT_HIGHP float holoinject_tol = holoinject_mode == 0.0 || holoinject_mode == 2.0 ? 1e-6 : 0.0;
    bool holoinject_at_far = abs(holoinject_p.z - holoinject_far_z) <= holoinject_tol * abs(holoinject_p.w);
    HOLOINJECT_HIGHP float holoinject_c = holoinject_at_far ? 0.0 : holoinject_view.y;
    if (holoinject_comfort.z > 0.0) {
        // k·w·R_p(1 - c/w) = w·u·R(s(1 - c/w)): c == 0 (far plane) is parallax 1, and w -> 0
        // gives R's front asymptote times 0, never 0/0.
        HOLOINJECT_HIGHP float holoinject_par = holoinject_c == 0.0 ? 1.0 : 1.0 - holoinject_c / holoinject_p.w;
        holoinject_p.x += holoinject_view.x * holoinject_p.w * holoinject_remap(holoinject_par, holoinject_comfort)
            + holoinject_view.z * holoinject_p.w;
        return holoinject_p;
    }
    holoinject_p.x += holoinject_view.x * (holoinject_p.w - holoinject_c) + holoinject_view.z * holoinject_p.w;
    return holoinject_p;
}
// The parallax this vertex's shift gives it, times w (the disparity record, DESIGN §5): the
// shifted x moves by k·(R(that / w)) + h, so every view's disparity is one number per vertex.
// Times w because w·p is affine in clip space, so perspective-correct interpolation gives the
// fragment its exact value, and p = (w·p)·gl_FragCoord.w there. Computed apart from the shift
// because the centre view (k = h = 0) returns early but is recorded too.
HOLOINJECT_HIGHP float holoinject_parallax_of(HOLOINJECT_HIGHP vec4 holoinject_p)
{
    HOLOINJECT_HIGHP float holoinject_mode = holoinject_view.w;
    if (holoinject_mode == 1.0 || (holoinject_mode == 2.0 && holoinject_p.w == 1.0))
        return 0.0;
    HOLOINJECT_HIGHP float holoinject_far_z = holoinject_mode == 3.0 ? 0.0 : holoinject_p.w;
    HOLOINJECT_HIGHP float holoinject_tol = holoinject_mode == 0.0 || holoinject_mode == 2.0 ? 1e-6 : 0.0;
    bool holoinject_at_far = abs(holoinject_p.z - holoinject_far_z) <= holoinject_tol * abs(holoinject_p.w);
    HOLOINJECT_HIGHP float holoinject_c = holoinject_at_far ? 0.0 : holoinject_view.y;
    // Before the comfort remap: its readers remap (the warps) or measure against the
    // comfortable range (the depth of field) themselves, as they do a depth's parallax.
    return holoinject_p.w - holoinject_c;
}
