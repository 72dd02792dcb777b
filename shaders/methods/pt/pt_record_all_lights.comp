#version 460
// pt_record for scenes with punctual lights or an environment beside their emitters
// (pt_record_kernel.glsl).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#define PMCR_OTHER_LIGHTS
#include "methods/pt/pt_record_kernel.glsl"
