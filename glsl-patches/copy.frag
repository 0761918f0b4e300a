#version 330 core
// The presenter's staged output copied pixel for pixel into a multisampled window (a blit
// cannot scale into one, nor on ES write into one at all): every sample of a pixel gets the
// pixel's value. The pass draws to a viewport at the window's origin.

uniform sampler2D u_image;

out vec4 frag_color;

void main()
{
    frag_color = texelFetch(u_image, ivec2(gl_FragCoord.xy), 0);
}
