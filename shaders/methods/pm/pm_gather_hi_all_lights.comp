#version 460
// Photon mapping's gather with PMC-HI direct lighting and PMC-IP feedback (pm-pmc), for scenes
// with punctual lights or an environment beside their emitters.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_control_flow_attributes : require
#define PMCR_OTHER_LIGHTS
#define PM_PMC_HI
#include "methods/pm/pm_gather_kernel.glsl"
