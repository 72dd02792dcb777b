#version 460
// Photon shooting (pm, pm-pmc) for scenes lit by emitters, punctual lights and an environment.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#define PMCR_OTHER_LIGHTS
#include "methods/pm/photon_shoot_kernel.glsl"
