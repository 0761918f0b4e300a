#version 330 core
// Transform feedback particle update: never rasterized, no gl_Position.
in vec3 inPos;
in vec3 inVel;
out vec3 outPos;
out vec3 outVel;
uniform float dt;
void main()
{
    outVel = inVel + vec3(0.0, -9.81, 0.0) * dt;
    outPos = inPos + outVel * dt;
}
