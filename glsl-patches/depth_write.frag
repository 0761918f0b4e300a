#version 330 core
// A depth copy where glBlitFramebuffer cannot make one: depth blits need the same depth
// bits and type at both ends. Each fragment of the destination rectangle `dst` (window
// pixels: x, y, w, h) takes the nearest texel of the source rectangle `src` (texels) of a
// depth texture, written as its depth; colour writes are masked off by the pass.

uniform sampler2D depth;
uniform vec4 src;
uniform vec4 dst;

void main()
{
    vec2 t = (gl_FragCoord.xy - dst.xy) / dst.zw;
    ivec2 texel = ivec2(src.xy + floor(t * src.zw));
    gl_FragDepth = texelFetch(depth, texel, 0).r;
}
