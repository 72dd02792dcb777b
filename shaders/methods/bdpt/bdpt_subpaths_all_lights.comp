#version 460
// Bidirectional path tracing's subpaths kernel (bdpt_subpaths_kernel.glsl), for scenes with punctual
// lights or an environment beside their emitters.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#define PMCR_OTHER_LIGHTS
#include "methods/bdpt/bdpt_subpaths_kernel.glsl"
