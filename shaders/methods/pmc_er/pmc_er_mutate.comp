#version 460
// pmc_er_mutate for scenes lit by emitters alone (pmc_er_mutate_kernel.glsl).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "methods/pmc_er/pmc_er_mutate_kernel.glsl"
