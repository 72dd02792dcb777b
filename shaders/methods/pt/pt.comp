#version 460
// Path tracing with NEE and MIS (the baseline): one camera sample's radiance per estimate.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock { PtPush push; };

#include "common/film.glsl"
#include "methods/pt/path_tracer.glsl"

// Paths in turn from pathBegin / pathBounce (camera_sample_kernel.glsl), every source.
#define CAMERA_SAMPLE_PATH_STATES
#include "methods/pt/camera_sample_kernel.glsl"
