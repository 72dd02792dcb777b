#version 460
// PMC-HI adaptive direct lighting for scenes with punctual lights or an environment beside
// their emitters: the environment one more mixture component, the punctual lights a separate
// next-event estimate (pmc_hi.glsl).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_control_flow_attributes : require
#define PMCR_OTHER_LIGHTS
#include "methods/pmc_hi/pmc_hi_kernel.glsl"
