#version 460
// mlt_chains for scenes lit by emitters alone (mlt_chains_kernel.glsl).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "methods/mlt/mlt_chains_kernel.glsl"
