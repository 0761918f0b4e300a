#version 330 core
// Red/cyan anaglyph of two quilt views with Dubois' least-squares matrices (2001), which keep
// colours far better than a plain channel split. Rows of each matrix give output R, G, B.

uniform sampler2D u_quilt;
uniform ivec4 u_left;   // tile rectangle (x, y, w, h) of the left-eye view, in quilt texels
uniform ivec4 u_right;
uniform ivec2 u_out_size;
uniform bool u_flipped; // the quilt's rows are stored top-down, as the window's are

out vec4 frag_color;

const mat3 LEFT = mat3(0.456, -0.040, -0.015,
                       0.500, -0.038, -0.021,
                       0.176, -0.016, -0.005);
const mat3 RIGHT = mat3(-0.043, 0.378, -0.072,
                        -0.088, 0.734, -0.113,
                        -0.002, -0.018, 1.226);

vec3 fetch(ivec4 tile, vec2 uv)
{
    ivec2 t = min(ivec2(uv * vec2(tile.zw)), tile.zw - 1);
    ivec2 p = tile.xy + t;
    if (u_flipped) p.y = textureSize(u_quilt, 0).y - 1 - p.y;
    return texelFetch(u_quilt, p, 0).rgb;
}

void main()
{
    vec2 uv = (gl_FragCoord.xy) / vec2(u_out_size);
    vec3 c = LEFT * fetch(u_left, uv) + RIGHT * fetch(u_right, uv);
    frag_color = vec4(clamp(c, 0.0, 1.0), 1.0);
}
