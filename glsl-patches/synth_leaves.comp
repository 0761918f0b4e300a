#version 430 core
// The adaptive quad grid (Didyk et al. 2011): one dispatch per pyramid level, coarsest
// first. A cell is flat enough when, in pixels of the outermost target view, its parallax
// range is within the threshold (Didyk's test), or a quad's interpolation error over it is
// (second-difference bound times cell²/8: planes warp exactly whatever their depth range).
// It is a leaf when it is flat enough and its parent is not (both bounds only shrink towards
// the leaves, so every ancestor was split).
// Leaves are appended to a list that feeds one draw per target view; each carries
// the parallax at its four corners (the farthest of the four pixels around each corner, so
// quads on a depth edge stretch across the disocclusion with the background).
layout(local_size_x = 8, local_size_y = 8) in;

uniform sampler2DArray u_level;
uniform sampler2DArray u_parent;
uniform int u_cell;
uniform int u_top;

void main()
{
    ivec2 cell = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(cell, textureSize(u_level, 0).xy))) {
        return;
    }
    if (u_top == 0 && flat_enough(texelFetch(u_parent, ivec3(cell / 2, u_layer), 0), float(2 * u_cell))) {
        return;
    }
    ivec2 xy = cell * u_cell;
    if (flat_enough(texelFetch(u_level, ivec3(cell, u_layer), 0), float(u_cell))) {
        emit(xy, min(ivec2(u_cell), u_tile - xy));
    }
    // Cells of 2x2 pixels still too deep are left to the column pass (synth_columns.comp).
}
