#version 330 core
// The comfort pass (src/output/comfort.rs): background depth of field and edge fade, driven
// by the outermost view's disparity D (tile px, + behind the screen) of each pixel, as the
// remap leaves it. depth_remap.glsl is inserted after #version, and one stage is defined:
//   COMFORT_MARK    nothing: drawn with the colour masked, it marks drawn pixels in the
//                   stencil of the pass's own copy of the depth;
//   COMFORT_HALF    the pre-blurred image: the quilt's colour at half size, with each
//                   texel's circle of confusion (over u_radius) in alpha, so a tap of the
//                   blur is one texel fetch;
//   COMFORT_DOF     blurs the quilt's background pixels (drawn, behind B) from it;
//   COMFORT_FADE    blends the clear colour over the border bands' foreground pixels.
// Every stage is drawn at a depth threshold with the depth (and stencil) test on, so the
// rasteriser drops most pixels an effect leaves alone before shading: a software rasteriser
// runs the whole shader for every pixel that reaches it, whatever it discards. The shader
// then weighs each pixel by its exact disparity.
uniform sampler2D u_depth;  // the quilt's window depth, copied (rows as the quilt stores them)
uniform ivec4 u_tile;       // this view's tile (x, y, w, h) in stored texels
uniform vec4 u_model;       // (a_hi, a_lo, c/b, S): parallax p = 1 - (c/b)(z + a); D = R(S·p)
uniform vec4 u_remap;       // the remap in tile px (off: z <= 0)
uniform vec4 u_range;       // the comfortable range (F, B, D_F, D_B) the effects measure from
uniform float u_radius;     // largest blur radius in px
uniform float u_far_depth;  // window depth where nothing was drawn (1, or 0 under reversed-Z)
uniform bool u_flipped;     // rows stored top-down, as the window's are
uniform bool u_zero_to_one; // glClipControl(.., GL_ZERO_TO_ONE): window depth is NDC depth
uniform sampler2D u_color;  // HALF: the quilt's colour (its magnification filter is linear)
uniform sampler2D u_half;   // DOF: COMFORT_HALF's image, rows as stored
uniform float u_fade;       // FADE: edge band in px
uniform vec4 u_background;  // FADE: what the fade goes to: the app's clear colour
out vec4 frag_color;

// 12 taps of a Poisson disc of radius 1 (minimum distance 0.4, generated once by dart throwing).
const vec2 TAPS[12] = vec2[](
    vec2(-0.326, -0.406), vec2(-0.840, -0.074), vec2(-0.696, 0.457), vec2(-0.203, 0.621),
    vec2(0.962, -0.195), vec2(0.473, -0.480), vec2(0.519, 0.767), vec2(0.185, -0.893),
    vec2(0.507, 0.064), vec2(0.896, 0.412), vec2(-0.322, -0.933), vec2(-0.792, -0.598));

float disparity_of(float d)
{
    float z = u_zero_to_one ? d : 2.0 * d - 1.0;
    float q = (z + u_model.x) + u_model.y;
    return holoinject_remap(u_model.w * (1.0 - u_model.z * q), u_remap);
}

float disparity(ivec2 p)
{
    return disparity_of(texelFetch(u_depth, p, 0).r);
}

// Blur radius for disparity D: zero up to B (the foreground and the comfortable range are
// never blurred), growing linearly to u_radius at the back asymptote.
float coc(float D)
{
    return u_radius * clamp((D - u_range.y) / max(u_range.w - u_range.y, 1.0), 0.0, 1.0);
}

// The stored texel this fragment covers (the quilt's framebuffer may store rows top-down).
ivec2 stored_texel()
{
    ivec2 p = ivec2(gl_FragCoord.xy);
    if (u_flipped)
        p.y = textureSize(u_depth, 0).y - 1 - p.y;
    return p;
}

#ifdef COMFORT_MARK
void main()
{
}
#endif

#ifdef COMFORT_HALF
// Drawn unflipped, in stored rows: texel h covers quilt texels 2h .. 2h + 1.
void main()
{
    ivec2 h = ivec2(gl_FragCoord.xy);
    vec2 size = vec2(textureSize(u_color, 0));
    // Between four texels, at level 0 (magnified): their average.
    vec3 c = textureLod(u_color, (vec2(2 * h) + 1.0) / size, 0.0).rgb;
    frag_color = vec4(c, coc(disparity(min(2 * h, ivec2(size) - 1))) / max(u_radius, 1e-6));
}
#endif

#ifdef COMFORT_DOF
// Agus et al.'s variable kernel: 12 Poisson taps of the half-size, pre-blurred image around
// the pixel, over its circle of confusion; the pixel itself is the 13th, through the blend.
void main()
{
    ivec2 p = stored_texel();
    float d = texelFetch(u_depth, p, 0).r;
    float r = coc(disparity_of(d));
    // Where nothing was drawn (culled by the stencil when there is one) the clear colour
    // stays: blurring it would cost every empty pixel the taps.
    if (r < 0.5 || d == u_far_depth)
        discard;
    ivec2 last = textureSize(u_half, 0) - 1;
    vec3 sum = vec3(0.0);
    float weight = 0.0;
    for (int k = 0; k < 12; k++) {
        ivec2 q = clamp(p + ivec2(TAPS[k] * r), u_tile.xy, u_tile.xy + u_tile.zw - 1);
        // A tap nearer (sharper) than this pixel would bleed the foreground into the
        // background: it counts only as much as it is blurred itself.
        vec4 t = texelFetch(u_half, min(q / 2, last), 0);
        float w = clamp(t.a * u_radius / r, 0.0, 1.0);
        sum += w * t.rgb;
        weight += w;
    }
    // (sum + own) / (weight + 1), with own the quilt's pixel under the blend.
    frag_color = vec4(sum, weight) / (weight + 1.0);
}
#endif

#ifdef COMFORT_FADE
void main()
{
    ivec2 p = stored_texel();
    float D = disparity(p);
    float x = float(p.x - u_tile.x) + 0.5;
    float border = min(x, float(u_tile.z) - x);
    // Nearer the viewer and nearer the border fade more; at -F and on the border, fully.
    float front = clamp(-D / max(u_range.x, 1.0), 0.0, 1.0);
    float a = front * (1.0 - smoothstep(0.0, u_fade, border));
    if (a <= 0.0)
        discard;
    frag_color = vec4(u_background.rgb * a, a);
}
#endif
