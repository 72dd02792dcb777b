#version 460
// MIS direct lighting (the PMC-HI baseline), for scenes lit by emitters alone
// (direct_all_lights.comp: also punctual lights and an environment).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "methods/pt/direct_kernel.glsl"
