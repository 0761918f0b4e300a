// glmark2 shader effect-2d.vert (/usr/share/glmark2/shaders/effect-2d.vert, glmark2-x11 2021.12).
// The lines up to the blank line are what glmark2's ShaderSource prepends at run time.
#ifdef GL_ES
precision mediump float;
#endif

attribute vec3 position;

varying vec2 TextureCoord;

void main(void)
{
    gl_Position = vec4(position, 1.0);

    TextureCoord = position.xy * 0.5 + 0.5;
}
