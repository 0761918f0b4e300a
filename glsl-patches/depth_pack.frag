#version 330 core
// Depth read-back where glReadPixels cannot read depth (OpenGL ES): each pixel's window
// depth (0..1), taken from a depth texture, is written as a 24-bit integer in the red
// (high), green and blue (low) bytes of an RGBA8 target, which every ES 3 context can read
// back; the CPU unpacks d = (r*65536 + g*256 + b) / (2^24 - 1). 24 bits are all a 24-bit
// depth buffer holds, and finer than the convergence estimate needs for 32-bit float depth.

uniform sampler2D depth;
out vec4 packed_depth;

void main()
{
    float d = clamp(texelFetch(depth, ivec2(gl_FragCoord.xy), 0).r, 0.0, 1.0);
    // round(), not + 0.5: 16777215.5 is not a float and would round up to 2^24.
    uint v = min(uint(round(d * 16777215.0)), 16777215u);
    packed_depth = vec4(float(v >> 16u), float((v >> 8u) & 255u), float(v & 255u), 255.0) / 255.0;
}
