#version 330 core
// The disparity record of one rendered view written into the comfort pass's depth copy as the
// window depth the scene's camera would give that parallax (src/output/comfort_record.rs), so
// the depth of field reads each recorded pixel's own disparity: a scene drawn off-screen and
// composited (its quilt depth is the composite's), a weapon in its own depth range, a sky at
// infinity. Pixels nothing recorded keep the quilt's depth, or take the depth of the scene's
// framebuffer when the scene is drawn off-screen.
uniform sampler2D u_quilt_record;       // the quilt's record (u_layer < 0), rows as stored
uniform sampler2DArray u_shadow_record; // the scene framebuffer's record, one layer per view
uniform sampler2DArray u_shadow_depth;  // and its depth, as the camera (or a warp) left it
uniform int u_layer;
uniform ivec4 u_tile;       // the tile in window coordinates (x, y, w, h)
uniform ivec2 u_src_size;   // the record's size (a shadow's layers may be scaled)
uniform int u_quilt_rows;   // the quilt's height when stored top-down, else 0
uniform int u_shadow_flipped; // the scene framebuffer is presented upside down (wined3d)
// (a_hi, a_lo, c/b, zero_to_one): p = 1 - (c/b)((z + a_hi) + a_lo), inverted.
uniform vec4 u_model;

void main()
{
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec2 rec;
    if (u_layer < 0) {
        ivec2 at = u_quilt_rows > 0 ? ivec2(px.x, u_quilt_rows - 1 - px.y) : px;
        rec = texelFetch(u_quilt_record, at, 0).rg;
        // Unrecorded: the quilt's own depth is the scene's (a fixed-function draw's, a warp's).
        if (rec.g < 0.5)
            discard;
    } else {
        vec2 local = (gl_FragCoord.xy - vec2(u_tile.xy)) / vec2(u_tile.zw);
        if (u_shadow_flipped != 0)
            local.y = 1.0 - local.y;
        ivec2 at = clamp(ivec2(local * vec2(u_src_size)), ivec2(0), u_src_size - 1);
        rec = texelFetch(u_shadow_record, ivec3(at, u_layer), 0).rg;
        // Unrecorded: the quilt's depth is the composite's, the scene's is in its framebuffer.
        if (rec.g < 0.5) {
            gl_FragDepth = texelFetch(u_shadow_depth, ivec3(at, u_layer), 0).r;
            return;
        }
    }
    float z = (1.0 - rec.r) / u_model.z - u_model.x - u_model.y;
    z = clamp(z, -1.0, 1.0);
    gl_FragDepth = u_model.w > 0.5 ? max(z, 0.0) : z * 0.5 + 0.5;
}
