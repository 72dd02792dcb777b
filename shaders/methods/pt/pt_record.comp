#version 460
// pt_record for scenes lit by emitters alone (pt_record_kernel.glsl).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "methods/pt/pt_record_kernel.glsl"
