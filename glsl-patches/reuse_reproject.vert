#version 330 core
// --reuse following the camera (synth/reproject.rs): one pixel of a view's kept render,
// moved to where the camera sees it now and drawn as a one-pixel point at its new depth, so
// the depth test keeps the nearest of the pixels landing together. Drawn with
// glDrawArrays(GL_POINTS, 0, w·h): the pixel (tile coordinates, bottom-up) is gl_VertexID.
uniform sampler2D u_color;
uniform sampler2D u_depth;
// The tile's first texel in the kept textures, and whether rows are stored top-down.
uniform ivec2 u_origin;
uniform int u_flip;
uniform ivec2 u_tile;
// The pixel's clip coordinates move to u_motion · clip + u_offset (camera::ViewRig::
// clip_motion): the view's shift undone, the camera's motion, the shift redone.
uniform mat4 u_motion;
uniform vec4 u_offset;
// (a, b) of the depth model z_ndc = -a + b/w, and the window depth of the far plane.
uniform vec2 u_model;
uniform float u_far;
// 1 when window depth is z_ndc (glClipControl GL_ZERO_TO_ONE), else 0.
uniform int u_zero_to_one;
flat out vec3 v_color;

void main()
{
    ivec2 p = ivec2(gl_VertexID % u_tile.x, gl_VertexID / u_tile.x);
    ivec2 t = u_origin + ivec2(p.x, u_flip == 1 ? u_tile.y - 1 - p.y : p.y);
    float d = texelFetch(u_depth, t, 0).r;
    float z = u_zero_to_one == 1 ? d : 2.0 * d - 1.0;
    float w = u_model.y / (z + u_model.x);
    vec2 ndc = (vec2(p) + 0.5) / vec2(u_tile) * 2.0 - 1.0;
    gl_Position = u_motion * vec4(ndc * w, z * w, w) + u_offset;
    // Sky (at infinity, no position to move) and anything behind the camera: not drawn,
    // the synthesised view shows it.
    if (d == u_far || !(w > 0.0) || !(gl_Position.w > 0.0))
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    gl_PointSize = 1.0;
    v_color = texelFetch(u_color, t, 0).rgb;
}
