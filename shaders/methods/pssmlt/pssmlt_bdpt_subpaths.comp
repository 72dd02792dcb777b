#version 460
// pssmlt_bdpt_subpaths for scenes lit by emitters alone (pssmlt_bdpt_subpaths_kernel.glsl).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "methods/pssmlt/pssmlt_bdpt_subpaths_kernel.glsl"
