#version 450
#extension GL_ARB_shader_viewport_layer_array : require
layout(location = 0) in vec3 pos;
uniform mat4 viewProj[6];
void main()
{
    gl_Layer = gl_InstanceID;
    gl_Position = viewProj[gl_InstanceID] * vec4(pos, 1.0);
}
