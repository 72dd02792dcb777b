#version 460
// Photon shooting (pm, pm-pmc) for scenes lit by emitters alone (photon_shoot_all_lights.comp: also
// punctual lights and an environment).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "methods/pm/photon_shoot_kernel.glsl"
