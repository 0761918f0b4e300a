#version 120
uniform mat4 projectionMatrix;
uniform mat4 modelViewMatrix;
attribute vec3 vertex;
varying float depth;
void main(void)
{
    vec4 eye = modelViewMatrix * vec4(vertex, 1.0);
    depth = -eye.z;
    gl_Position = projectionMatrix * eye;
}
