#version 460
// pmc_er_seed for scenes lit by emitters alone (pmc_er_seed_kernel.glsl).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_shader_atomic_float : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "methods/pmc_er/pmc_er_seed_kernel.glsl"
