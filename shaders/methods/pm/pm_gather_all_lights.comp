#version 460
// Photon mapping's gather with MIS direct lighting (pm), for scenes
// with punctual lights or an environment beside their emitters.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#define PMCR_OTHER_LIGHTS
#include "methods/pm/pm_gather_kernel.glsl"
