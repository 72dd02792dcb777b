#version 460
// Photon mapping's gather with PMC-HI direct lighting and PMC-IP feedback (pm-pmc), for scenes
// lit by emitters alone (pm_gather_hi_all_lights.comp: also punctual lights and an environment).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_control_flow_attributes : require
#define PM_PMC_HI
#include "methods/pm/pm_gather_kernel.glsl"
