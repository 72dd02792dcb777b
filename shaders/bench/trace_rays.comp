#version 460
// Traces a buffer of rays against the scene BVH: closest hits (or occlusion) into a buffer.
// Used by bench/throughput to measure traversal speed apart from shading.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "bench/trace_rays.glsl"
