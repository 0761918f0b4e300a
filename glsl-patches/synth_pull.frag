#version 330 core
// Pull (Gortler et al. 1996; Grossman & Dally 1998): one level of the hole-filling pyramid
// from the level below, premultiplied colour and coverage weight summed over 2x2 texels and
// divided by max(weight, 1): a texel with any covered pixel under it becomes fully covered by
// their mean, a sparse one keeps its partial weight.
uniform sampler2D u_src;
out vec4 o_color;

void main()
{
    ivec2 c = 2 * ivec2(gl_FragCoord.xy);
    ivec2 size = textureSize(u_src, 0);
    vec4 sum = vec4(0.0);
    for (int i = 0; i < 4; i++) {
        ivec2 p = c + ivec2(i & 1, i >> 1);
        if (p.x < size.x && p.y < size.y) {
            sum += texelFetch(u_src, p, 0);
        }
    }
    o_color = sum / max(sum.a, 1.0);
}
