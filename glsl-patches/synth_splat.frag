#version 330 core
// A splatted pixel: its colour, alpha 1 marking "covered" for the hole filling (holes keep
// the clear's alpha 0).
flat in vec3 v_color;
out vec4 o_color;

void main()
{
    o_color = vec4(v_color, 1.0);
}
