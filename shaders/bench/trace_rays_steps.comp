#version 460
// trace_rays.comp that also counts each ray's traversal steps (bench/throughput --steps): a
// hit's b1 and b2 hold the wide-node and leaf steps as uint bits.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#define BVH_COUNT_STEPS
#include "bench/trace_rays.glsl"
