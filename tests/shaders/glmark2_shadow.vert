// glmark2 shader shadow.vert (/usr/share/glmark2/shaders/shadow.vert, glmark2-x11 2021.12).
// The lines up to the blank line are what glmark2's ShaderSource prepends at run time.
#ifdef GL_ES
precision mediump float;
#endif
const vec4 MaterialDiffuse = vec4(0.7, 0.7, 0.7, 1.0);

attribute vec2 position;

uniform mat4 LightMatrix;
uniform mat4 ModelViewProjectionMatrix;

varying vec4 ShadowCoord;
varying vec4 Color;

void main()
{
    Color = MaterialDiffuse;

    vec4 pos4 = vec4(position, 0.0, 1.0);
    ShadowCoord = LightMatrix * pos4;
    gl_Position = ModelViewProjectionMatrix * pos4;
}
