// holoinject: the comfort remap R of DESIGN section 3 (src/camera/comfort.rs is its f64 twin
// and says why this form). r = (F, B, D_F, D_B) in the units of x (a disparity, or a parallax
// scaled by the CPU); r.z <= 0 means off (identity). Identity on [-F, B]; beyond B,
// D_B - g^2/(t + g) with g = D_B - B and t = x - B (value B, slope 1 at the join, D_B at
// infinity, never NaN for t = inf); mirrored in front of -F.
// Valid GLSL 1.10 .. 4.60 and ES 1.00 .. 3.20 (no f suffixes, no const initialisers).
#ifndef HOLOINJECT_HIGHP
#ifdef GL_ES
#define HOLOINJECT_HIGHP highp
#else
#define HOLOINJECT_HIGHP
#endif
#endif
HOLOINJECT_HIGHP float holoinject_remap(HOLOINJECT_HIGHP float x, HOLOINJECT_HIGHP vec4 r)
{
    if (r.z <= 0.0)
        return x;
    if (x > r.y) {
        HOLOINJECT_HIGHP float g = r.w - r.y;
        return r.w - g * (g / ((x - r.y) + g));
    }
    if (x < -r.x) {
        HOLOINJECT_HIGHP float g = r.z - r.x;
        return -(r.z - g * (g / ((-r.x - x) + g)));
    }
    return x;
}
