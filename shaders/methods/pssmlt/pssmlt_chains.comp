#version 460
// pssmlt_chains for scenes lit by emitters alone (pssmlt_chains_kernel.glsl).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "methods/pssmlt/pssmlt_chains_kernel.glsl"
