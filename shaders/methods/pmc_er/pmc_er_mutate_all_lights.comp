#version 460
// pmc_er_mutate for scenes with punctual lights or an environment beside their emitters
// (pmc_er_mutate_kernel.glsl).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#define PMCR_OTHER_LIGHTS
#include "methods/pmc_er/pmc_er_mutate_kernel.glsl"
