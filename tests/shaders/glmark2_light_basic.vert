// glmark2 shader light-basic.vert (/usr/share/glmark2/shaders/light-basic.vert, glmark2-x11 2021.12).
// The lines up to the blank line are what glmark2's ShaderSource prepends at run time.
#ifdef GL_ES
precision mediump float;
#endif
const vec4 LightSourcePosition = vec4(20.0, 20.0, 10.0, 1.0);
const vec4 MaterialDiffuse = vec4(0.7, 0.7, 0.7, 1.0);

attribute vec3 position;
attribute vec3 normal;
attribute vec2 texcoord;

uniform mat4 ModelViewProjectionMatrix;
uniform mat4 NormalMatrix;

varying vec4 Color;
varying vec2 TextureCoord;

void main(void)
{
    // Transform the normal to eye coordinates
    vec3 N = normalize(vec3(NormalMatrix * vec4(normal, 1.0)));

    // The LightSourcePosition is actually its direction for directional light
    vec3 L = normalize(LightSourcePosition.xyz);

    // Multiply the diffuse value by the vertex color (which is fixed in this case)
    // to get the actual color that we will use to draw this vertex with
    float diffuse = max(dot(N, L), 0.0);
    Color = vec4(diffuse * MaterialDiffuse.rgb, MaterialDiffuse.a);

    // Set the texture coordinates as a varying
    TextureCoord = texcoord;

    // Transform the position to clip coordinates
    gl_Position = ModelViewProjectionMatrix * vec4(position, 1.0);
}
