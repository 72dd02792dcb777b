#version 460
// Path tracing with NEE and MIS (the baseline), for scenes lit by emitters alone
// (pt_all_lights.comp: also punctual lights and an environment).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "methods/pt/pt_kernel.glsl"
