// glmark2 shader desktop.vert (/usr/share/glmark2/shaders/desktop.vert, glmark2-x11 2021.12).
// The lines up to the blank line are what glmark2's ShaderSource prepends at run time.
#ifdef GL_ES
precision mediump float;
#endif

attribute vec2 position;
attribute vec2 texcoord;

varying vec2 TextureCoord;

void main(void)
{
    gl_Position = vec4(position, 0.0, 1.0);

    TextureCoord = texcoord;
}
