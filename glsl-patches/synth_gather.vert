#version 430 core
// The gather warp (synth_gather.frag): one instance per synthesised view, a quad over its
// tile of the destination, with the view's parameters passed on flat.
struct Target {
    // (a, b) of the preferred source, then of the second: a source pixel at x with parallax
    // p lands at x + a·p + b in this view.
    vec4 ab;
    // Source layers (preferred, second) and how many sources (1 or 2).
    ivec4 src;
    // The tile: x, y, w, h in the destination.
    ivec4 rect;
};
layout(std430, binding = 0) readonly buffer Targets { Target targets[]; };
uniform vec2 u_dest;
flat out vec4 v_ab;
flat out ivec3 v_src;
flat out ivec2 v_origin;

void main()
{
    Target t = targets[gl_InstanceID];
    // Two triangles: corners (0,0) (1,0) (0,1), (0,1) (1,0) (1,1).
    int k = gl_VertexID % 6;
    vec2 corner = vec2(k == 1 || k == 4 || k == 5 ? 1.0 : 0.0, k == 2 || k == 3 || k == 5 ? 1.0 : 0.0);
    vec2 pixel = vec2(t.rect.xy) + corner * vec2(t.rect.zw);
    gl_Position = vec4(pixel / u_dest * 2.0 - 1.0, 0.0, 1.0);
    v_ab = t.ab;
    v_src = t.src.xyz;
    v_origin = t.rect.xy;
}
