#version 460
// MIS direct lighting (the PMC-HI baseline).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock { PtPush push; };

#include "common/film.glsl"
#include "methods/pt/path_tracer.glsl"

vec3 estimateRadiance(vec2 raster, inout Sampler s, inout uint rays, uint recordIndex) {
    return directLighting(raster, s, push.lightSamples, rays);
}

#include "methods/pt/camera_sample_kernel.glsl"
