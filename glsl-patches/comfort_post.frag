#version 330 core
// Comfort post-pass over one view's tile (src/output/comfort.rs): edge fade and background
// depth of field, both driven by the outermost view's disparity D (tile px, + behind the
// screen) of each pixel, as the remap leaves it. depth_remap.glsl is inserted after #version,
// and `#define HOLOINJECT_DOF` with --dof: llvmpipe runs both sides of a branch, so the taps
// would cost every pixel even with the blur off.
uniform sampler2D u_color;  // the quilt's colour, copied (rows as the quilt stores them)
uniform sampler2D u_half;   // the same at half size, linearly filtered: the pre-blurred image
uniform sampler2D u_depth;  // the quilt's window depth, copied
uniform ivec4 u_tile;       // this view's tile (x, y, w, h) in stored texels
uniform bool u_flipped;     // rows stored top-down, as the window's are
uniform vec4 u_model;       // (a_hi, a_lo, c/b, S): parallax p = 1 - (c/b)(z + a); D = R(S·p)
uniform vec4 u_remap;       // the remap in tile px (off: z <= 0)
uniform vec4 u_range;       // the comfortable range (F, B, D_F, D_B) the effects measure from
uniform float u_fade;       // edge band in px (0: off)
uniform float u_radius;     // largest blur radius in px (0: off)
uniform vec4 u_background;  // what the fade goes to: the app's clear colour
uniform float u_far_depth;  // window depth where nothing was drawn (1, or 0 under reversed-Z)
out vec4 frag_color;

// 12 taps of a Poisson disc of radius 1 (minimum distance 0.4, generated once by dart throwing).
const vec2 TAPS[12] = vec2[](
    vec2(-0.326, -0.406), vec2(-0.840, -0.074), vec2(-0.696, 0.457), vec2(-0.203, 0.621),
    vec2(0.962, -0.195), vec2(0.473, -0.480), vec2(0.519, 0.767), vec2(0.185, -0.893),
    vec2(0.507, 0.064), vec2(0.896, 0.412), vec2(-0.322, -0.933), vec2(-0.792, -0.598));

float disparity(ivec2 p)
{
    float d = texelFetch(u_depth, p, 0).r;
    float q = ((2.0 * d - 1.0) + u_model.x) + u_model.y;
    return holoinject_remap(u_model.w * (1.0 - u_model.z * q), u_remap);
}

// Blur radius for disparity D: zero up to B (the foreground and the comfortable range are
// never blurred), growing linearly to u_radius at the back asymptote.
float coc(float D)
{
    return u_radius * clamp((D - u_range.y) / max(u_range.w - u_range.y, 1.0), 0.0, 1.0);
}

vec3 blurred(ivec2 p, float r, vec3 own)
{
    vec2 size = vec2(textureSize(u_color, 0));
    vec3 sum = own;
    float weight = 1.0;
    for (int k = 0; k < 12; k++) {
        ivec2 q = clamp(p + ivec2(TAPS[k] * r), u_tile.xy, u_tile.xy + u_tile.zw - 1);
        // A tap nearer (sharper) than this pixel would bleed the foreground into the
        // background: it counts only as much as it is blurred itself.
        float w = clamp(coc(disparity(q)) / r, 0.0, 1.0);
        sum += w * texture(u_half, (vec2(q) + 0.5) / size).rgb;
        weight += w;
    }
    return sum / weight;
}

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy);
    if (u_flipped)
        p.y = textureSize(u_color, 0).y - 1 - p.y;
    vec4 c = texelFetch(u_color, p, 0);
    float D = disparity(p);
    float r = coc(D);
    // Where nothing was drawn the clear colour is uniform: gathering it is most of a deep
    // scene's cost (llvmpipe) and changes little, so only drawn pixels are blurred.
#ifdef HOLOINJECT_DOF
    if (r >= 0.5 && texelFetch(u_depth, p, 0).r != u_far_depth)
        c.rgb = blurred(p, r, c.rgb);
#endif
    if (u_fade > 0.0 && D < 0.0) {
        float x = float(p.x - u_tile.x) + 0.5;
        float border = min(x, float(u_tile.z) - x);
        // Nearer the viewer and nearer the border fade more; at -F and on the border, fully.
        float front = clamp(-D / max(u_range.x, 1.0), 0.0, 1.0);
        float edge = 1.0 - smoothstep(0.0, u_fade, border);
        c = mix(c, u_background, front * edge);
    }
    frag_color = c;
}
