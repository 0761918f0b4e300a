#version 120
// Written before 1.30/4.00 made `flat` and `sample` keywords: valid 1.20.
attribute vec3 sample;
attribute float flat;
uniform mat4 modelViewProjection;
varying float shade;
void main()
{
    shade = flat;
    gl_Position = modelViewProjection * vec4(sample, 1.0);
}
