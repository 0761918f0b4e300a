#version 330 core
// Parallax p = 1 - c/w of each pixel of a rendered view, from its window depth (see
// src/synth/disparity.rs for why q is formed before the multiplication).
uniform sampler2DArray u_depth;
uniform int u_layer;
// (a_hi, a_lo, c/b, unused)
uniform vec4 u_model;
out float o_parallax;

void main()
{
    float d = texelFetch(u_depth, ivec3(ivec2(gl_FragCoord.xy), u_layer), 0).r;
    float z = 2.0 * d - 1.0;
    float q = (z + u_model.x) + u_model.y;
    o_parallax = 1.0 - u_model.z * q;
}
