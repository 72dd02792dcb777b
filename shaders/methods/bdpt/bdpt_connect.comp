#version 460
// Bidirectional path tracing's connect kernel (bdpt_connect_kernel.glsl), for scenes lit by emitters
// alone (bdpt_connect_all_lights.comp: also punctual lights and an environment).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "methods/bdpt/bdpt_connect_kernel.glsl"
