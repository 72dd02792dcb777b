#version 460
// pssmlt_bdpt_connect for scenes with punctual lights or an environment beside their emitters
// (pssmlt_bdpt_connect_kernel.glsl).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#define PMCR_OTHER_LIGHTS
#include "methods/pssmlt/pssmlt_bdpt_connect_kernel.glsl"
