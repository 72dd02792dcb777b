#version 460
// Photon mapping's gather with MIS direct lighting (pm), for scenes
// lit by emitters alone (pm_gather_all_lights.comp: also punctual lights and an environment).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "methods/pm/pm_gather_kernel.glsl"
