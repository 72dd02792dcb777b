#version 460
// Path tracing with NEE and MIS (the baseline), for scenes with punctual lights or an
// environment (shaders/common/environment.glsl) beside their emitters.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#define PMCR_OTHER_LIGHTS
#include "methods/pt/pt_kernel.glsl"
