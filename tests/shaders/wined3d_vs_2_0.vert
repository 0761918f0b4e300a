#version 440
#extension GL_ARB_cull_distance : enable
#extension GL_ARB_gpu_shader5 : enable
#extension GL_ARB_shader_atomic_counters : enable
#extension GL_ARB_shader_bit_encoding : enable
#extension GL_ARB_shader_image_load_store : enable
#extension GL_ARB_shader_image_size : enable
#extension GL_ARB_shader_storage_buffer_object : enable
#extension GL_ARB_shader_texture_image_samples : enable
#extension GL_ARB_shading_language_420pack : enable
#extension GL_ARB_shading_language_packing : enable
#extension GL_ARB_texture_cube_map_array : enable
#extension GL_ARB_texture_gather : enable
#extension GL_ARB_texture_query_levels : enable
#extension GL_ARB_uniform_buffer_object : enable
#extension GL_ARB_viewport_array : enable
#extension GL_EXT_texture_array : enable
#extension GL_EXT_texture_shadow_lod : enable
#extension GL_ARB_draw_instanced : enable
#extension GL_ARB_explicit_attrib_location : enable
#extension GL_ARB_shader_viewport_layer_array : enable
invariant gl_Position;
uniform vec4 vs_c[256];
vec4 vs_out[12];
vec4 tmp0;
vec4 tmp1;
precise vec4 tmp_precise[2];
layout(location = 0) in vec4 vs_in0;
layout(location = 1) in vec4 vs_in1;
out vec4 ffp_varying_diffuse;
out vec4 ffp_varying_specular;
out vec4 ffp_varying_texcoord[8];
out float ffp_varying_fogcoord;
void setup_vs_output(in vec4[12]);
uniform vec4 pos_fixup;
void main()
{
vs_out[10].x = (dot(vs_in0.xyzw, vs_c[0].xyzw));
vs_out[10].y = (dot(vs_in0.xyzw, vs_c[1].xyzw));
vs_out[10].z = (dot(vs_in0.xyzw, vs_c[2].xyzw));
vs_out[10].w = (dot(vs_in0.xyzw, vs_c[3].xyzw));
vs_out[8].xyzw = (vs_in1.xyzw);
setup_vs_output(vs_out);
ffp_varying_fogcoord = 0.0;
gl_Position.y = gl_Position.y * pos_fixup.y;
gl_Position.xy += pos_fixup.zw * gl_Position.ww;
gl_Position.z = gl_Position.z * 2.0 - gl_Position.w;
}
