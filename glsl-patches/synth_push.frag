#version 330 core
// Push: a level's own premultiplied colour, its uncovered part filled from the (already
// filled) level above, interpolated bilinearly so filled holes are smooth rather than blocky.
// At level 0 (u_resolve) the result is un-premultiplied into the target tile, with the
// splatted depth (the far clear in holes) as the tile's depth, as the grid warp leaves it.
uniform sampler2D u_own;
uniform sampler2D u_coarse;
uniform sampler2D u_depth;
// Lower-left pixel of the viewport (the target tile when resolving, else 0).
uniform ivec2 u_origin;
uniform int u_resolve;
out vec4 o_color;

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy) - u_origin;
    vec4 own = texelFetch(u_own, p, 0);
    vec2 uv = (vec2(p) + 0.5) * 0.5 / vec2(textureSize(u_coarse, 0));
    vec4 c = own + (1.0 - own.a) * textureLod(u_coarse, uv, 0.0);
    if (u_resolve == 1) {
        o_color = vec4(c.rgb / max(c.a, 1.0e-6), 1.0);
        gl_FragDepth = texelFetch(u_depth, p, 0).r;
    } else {
        o_color = c;
    }
}
