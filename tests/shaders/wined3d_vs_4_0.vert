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
layout(std140, binding = 15) uniform block_vs_cb0 { vec4 vs_cb0[4]; };
vec4 vs_out[16];
vec4 R0;
vec4 R1;
vec4 R2;
vec4 R3;
vec4 R4;
vec4 R5;
vec4 R6;
vec4 tmp0;
vec4 tmp1;
precise vec4 tmp_precise[2];
layout(location = 0) in vec4 vs_in0;
layout(location = 1) in vec4 vs_in1;
uniform vec4 pos_fixup;
out shader_in_out {
    vec4 reg0;
    vec4 reg1;
    vec4 reg2;
    vec4 reg3;
    vec4 reg4;
    vec4 reg5;
    vec4 reg6;
    vec4 reg7;
    vec4 reg8;
    vec4 reg9;
    vec4 reg10;
    vec4 reg11;
    vec4 reg12;
    vec4 reg13;
    vec4 reg14;
    vec4 reg15;
    vec4 reg16;
    vec4 reg17;
    vec4 reg18;
    vec4 reg19;
    vec4 reg20;
    vec4 reg21;
    vec4 reg22;
    vec4 reg23;
    vec4 reg24;
    vec4 reg25;
    vec4 reg26;
    vec4 reg27;
    vec4 reg28;
    vec4 reg29;
    vec4 reg30;
} shader_out;
void setup_vs_output(in vec4 outputs[16])
{
gl_Position.xyzw = outputs[0].xyzw;
shader_out.reg0.xyzw = outputs[0].xyzw;
shader_out.reg1.xyzw = outputs[1].xyzw;
}
void main()
{
R0.xyzw = (vs_in1.xyzw);
R1.xyz = (vs_in0.xyz);
R1.w = (intBitsToFloat(0 /* 0.00000000e+00 */));
R2.xyzw = (vs_cb0[0].xyzw);
R1.w = (intBitsToFloat(0x4 /* 5.60519386e-45 */));
R3.xyzw = (vs_cb0[1].xyzw);
R1.w = (intBitsToFloat(0x8 /* 1.12103877e-44 */));
R4.xyzw = (vs_cb0[2].xyzw);
R1.w = (intBitsToFloat(0xc /* 1.68155816e-44 */));
R5.xyzw = (vs_cb0[3].xyzw);
R1.w = (intBitsToFloat(0x3f800000 /* 1.00000000e+00 */));
R6.x = (R1.x);
R6.y = (R1.y);
R1.x = (R1.z);
R1.y = (R2.x);
R1.y = (R6.x * R1.y);
R1.z = (R3.x);
R1.z = (R6.y * R1.z);
R1.y = (R1.y + R1.z);
R1.z = (R4.x);
R1.z = (R1.x * R1.z);
R1.y = (R1.y + R1.z);
R1.z = (R5.x);
R1.z = (R1.w * R1.z);
R1.y = (R1.y + R1.z);
R1.z = (R2.y);
R1.z = (R6.x * R1.z);
R6.z = (R3.y);
R6.z = (R6.y * R6.z);
R1.z = (R1.z + R6.z);
R6.z = (R4.y);
R6.z = (R1.x * R6.z);
R1.z = (R1.z + R6.z);
R6.z = (R5.y);
R6.z = (R1.w * R6.z);
R1.z = (R1.z + R6.z);
R6.z = (R2.z);
R6.z = (R6.x * R6.z);
R6.w = (R3.z);
R6.w = (R6.y * R6.w);
R6.z = (R6.z + R6.w);
R6.w = (R4.z);
R6.w = (R1.x * R6.w);
R6.z = (R6.z + R6.w);
R6.w = (R5.z);
R6.w = (R1.w * R6.w);
R6.z = (R6.z + R6.w);
R2.x = (R2.w);
R2.x = (R6.x * R2.x);
R2.y = (R3.w);
R2.y = (R6.y * R2.y);
R2.x = (R2.x + R2.y);
R2.y = (R4.w);
R1.x = (R1.x * R2.y);
R1.x = (R2.x + R1.x);
R2.x = (R5.w);
R1.w = (R1.w * R2.x);
R1.x = (R1.x + R1.w);
R1.w = (intBitsToFloat(0 /* 0.00000000e+00 */));
R2.x = (R1.y);
R1.y = (intBitsToFloat(0x1 /* 1.40129846e-45 */));
R2.y = (R1.z);
R1.y = (intBitsToFloat(0x2 /* 2.80259693e-45 */));
R2.z = (R6.z);
R1.y = (intBitsToFloat(0x3 /* 4.20389539e-45 */));
R2.w = (R1.x);
R1.xyzw = (R2.xyzw);
vs_out[0].xyzw = (R1.xyzw);
vs_out[1].xyzw = (R0.xyzw);
setup_vs_output(vs_out);
gl_Position.y = gl_Position.y * pos_fixup.y;
gl_Position.xy += pos_fixup.zw * gl_Position.ww;
gl_Position.z = gl_Position.z * 2.0 - gl_Position.w;
return;
}
