#version 460
// PMC-HI adaptive direct lighting for scenes lit by emitters alone (pmc_hi_all_lights.comp:
// also punctual lights and an environment).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_control_flow_attributes : require
#include "methods/pmc_hi/pmc_hi_kernel.glsl"
