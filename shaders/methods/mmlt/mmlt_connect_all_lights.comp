#version 460
// Multiplexed MLT's connect kernel (shared/pssmlt_types.h: the pssmlt_bdpt_connect body with
// PSS_MULTIPLEXED), for scenes with punctual lights or an environment beside their emitters.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#define PSS_MULTIPLEXED
#define PMCR_OTHER_LIGHTS
#include "methods/pssmlt/pssmlt_bdpt_connect_kernel.glsl"
