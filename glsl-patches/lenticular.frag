#version 330 core
// Native lenticular weave (DESIGN §4). This is src/output/weave.rs (the CPU reference)
// step for step: the same pixel-centre u, v, the same phase, the same cell patterns, the
// same filters, and texelFetch of the same quilt texel, so the two can be compared exactly.
//
// Per output pixel and colour channel ch:
//   phase = (u + dx + (v + dy) * tilt) * pitch' - center,  f = fract(phase),
//   view  = (invView ? 1 - f : f) * N
// Classic panels: (dx, dy) = (slot * subp, 0), slot = ch with R and B swapped by flipSubp.
// Gen3 panels: (dx, dy) = the offsets of colour ch in the pixel's sub-pixel cell.
// The quilt is the GL texture: view k at column k % cols, row k / cols from the bottom, except
// that the layer draws the two views of u_swap in each other's tile, and stores the rows
// top-down (as the window is stored) when u_flipped.
// Output pixels are gl_FragCoord: the pass draws to a viewport at the origin of its target.

const int MAX_CELLS = 16;
const int MAX_GAUSSIAN_RADIUS = 8;
const float ONE_BELOW = 0.99999994; // largest float below 1

uniform sampler2D u_quilt;
uniform ivec2 u_tile;
uniform float u_pitch;      // pitch' = pitch * (screenW / DPI) * cos(atan(1 / slope))
uniform float u_tilt;       // screenH / (screenW * slope), negated by flipImageX
uniform float u_subp;       // 1 / (3 * screenW), negated by flipImageX
uniform float u_center;
uniform bool u_inv_view;
uniform bool u_flip_subp;
uniform int u_view_count;
uniform int u_cols;
uniform int u_rows;
uniform int u_filter;       // 0 nearest, 1 blend with next view, 2 Gaussian over views
uniform float u_sigma;      // Gaussian sigma, in views
uniform int u_cell_pattern; // CellPatternMode
uniform int u_cell_count;   // 0: classic RGB stripe
// Offsets in u, v units (pixels / screenW, / screenH); colour ch of cell c at [3 * c + ch].
uniform vec2 u_cells[3 * MAX_CELLS];
uniform ivec2 u_out_size;
uniform bool u_flipped;
uniform ivec2 u_swap;       // (-1, -1) when no two views trade places

out vec4 frag_color;

int cell_index(ivec2 p)
{
    int cell = 0;
    if (u_cell_pattern == 1) cell = (p.x + p.y) % 2;
    else if (u_cell_pattern == 2) cell = p.y % 4;
    else if (u_cell_pattern == 3) cell = (p.y + 2 * (p.x % 2)) % 4;
    else if (u_cell_pattern == 4) cell = p.x % 2;
    return cell % u_cell_count;
}

vec2 subpixel_offset(ivec2 p, int ch)
{
    if (u_cell_count > 0) return u_cells[3 * cell_index(p) + ch];
    int slot = u_flip_subp ? 2 - ch : ch;
    return vec2(float(slot) * u_subp, 0.0);
}

float view_for(ivec2 p, vec2 uv, int ch)
{
    vec2 d = subpixel_offset(p, ch);
    float phase = (uv.x + d.x + (uv.y + d.y) * u_tilt) * u_pitch - u_center;
    float f = phase - floor(phase);
    if (u_inv_view) f = 1.0 - f;
    return clamp(f, 0.0, ONE_BELOW) * float(u_view_count);
}

// Channel ch of view k at tile coordinates uv, nearest texel.
float tap(int k, vec2 uv, int ch)
{
    // The tile size as the layer lays the quilt out: the texture may be wider (the guard
    // band's columns beyond the tiles).
    ivec2 tile = u_tile;
    ivec2 t = min(ivec2(uv * vec2(tile)), tile - 1);
    int cell = k == u_swap.x ? u_swap.y : (k == u_swap.y ? u_swap.x : k);
    ivec2 p = ivec2(cell % u_cols, cell / u_cols) * tile + t;
    if (u_flipped) p.y = textureSize(u_quilt, 0).y - 1 - p.y;
    return texelFetch(u_quilt, p, 0)[ch];
}

float gaussian(float view, int k0, vec2 uv, int ch)
{
    int last = u_view_count - 1;
    int radius = clamp(int(ceil(3.0 * u_sigma)), 1, MAX_GAUSSIAN_RADIUS);
    float sum = 0.0;
    float total = 0.0;
    for (int i = -MAX_GAUSSIAN_RADIUS; i <= MAX_GAUSSIAN_RADIUS + 1; i++) {
        int k = k0 + i;
        if (i < -radius || i > radius + 1 || k < 0 || k > last) continue;
        float d = view - float(k);
        float w = exp(-d * d / (2.0 * u_sigma * u_sigma));
        sum += w * tap(k, uv, ch);
        total += w;
    }
    // A sigma far below one view underflows every weight: that is nearest.
    return total > 1e-20 ? sum / total : tap(k0, uv, ch);
}

float channel(ivec2 p, vec2 uv, int ch)
{
    float view = view_for(p, uv, ch);
    int last = u_view_count - 1;
    int k0 = min(int(view), last);
    if (u_filter == 1) {
        // Never wraps from the last view to view 0: the cone's two ends differ most.
        float t = view - float(k0);
        return mix(tap(k0, uv, ch), tap(min(k0 + 1, last), uv, ch), t);
    }
    if (u_filter == 2) return gaussian(view, k0, uv, ch);
    return tap(k0, uv, ch);
}

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec2 uv = (vec2(p) + 0.5) / vec2(u_out_size);
    frag_color = vec4(channel(p, uv, 0), channel(p, uv, 1), channel(p, uv, 2), 1.0);
}
