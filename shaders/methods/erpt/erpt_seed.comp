#version 460
// erpt_seed for scenes lit by emitters alone (erpt_seed_kernel.glsl).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "methods/erpt/erpt_seed_kernel.glsl"
