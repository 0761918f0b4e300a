#version 330 core
// A warped fragment keeps its source pixel's depth (the view shift leaves z and w alone), so
// the depth test makes nearer surfaces win. Quads stretched over a disocclusion take the
// background's colour and lose every depth tie against surfaces actually seen there.
uniform sampler2DArray u_color;
uniform sampler2DArray u_depth;
uniform sampler2DArray u_parallax;
uniform int u_layer;
uniform vec2 u_tile;
// Towards the far side, in window depth: +2^-14, or negative under reversed-Z.
uniform float u_far_bias;
in vec2 v_uv;
flat in int v_stretched;
flat in int v_cell_x;
out vec4 o_color;

void main()
{
    vec2 uv = v_uv;
    if (v_stretched != 0) {
        // The farther of the pixels on either side of this one, in this row.
        int w = int(u_tile.x);
        int row = int(v_uv.y * u_tile.y);
        int left = max(v_cell_x - 1, 0), right = min(v_cell_x + 1, w - 1);
        float pl = texelFetch(u_parallax, ivec3(left, row, u_layer), 0).r;
        float pr = texelFetch(u_parallax, ivec3(right, row, u_layer), 0).r;
        uv.x = (float(pl >= pr ? left : right) + 0.5) / u_tile.x;
    }
    o_color = texture(u_color, vec3(uv, float(u_layer)));
    ivec2 px = clamp(ivec2(uv * u_tile), ivec2(0), ivec2(u_tile) - 1);
    float d = texelFetch(u_depth, ivec3(px, u_layer), 0).r;
    gl_FragDepth = clamp(v_stretched != 0 ? d + u_far_bias : d, 0.0, 1.0);
}
