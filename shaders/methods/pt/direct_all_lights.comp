#version 460
// MIS direct lighting (the PMC-HI baseline), for scenes with punctual lights or an
// environment beside their emitters.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#define PMCR_OTHER_LIGHTS
#include "methods/pt/direct_kernel.glsl"
