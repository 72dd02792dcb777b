#version 460
// Multiplexed MLT's subpaths kernel (shared/pssmlt_types.h: the pssmlt_bdpt_subpaths body with
// PSS_MULTIPLEXED), for scenes lit by emitters alone.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#define PSS_MULTIPLEXED
#include "methods/pssmlt/pssmlt_bdpt_subpaths_kernel.glsl"
