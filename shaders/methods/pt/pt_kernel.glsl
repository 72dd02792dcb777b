// The body of pt.comp and pt_all_lights.comp: path tracing with NEE and MIS, one camera
// sample's radiance per estimate. The host picks the variant by the scene's lights
// (pathTracingKernel, host/methods/pt/pt_integrator.h).
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock { PtPush push; };

#include "common/film.glsl"
#include "methods/pt/path_tracer.glsl"

// Paths in turn from pathBegin / pathBounce (camera_sample_kernel.glsl), every source.
#define CAMERA_SAMPLE_PATH_STATES
#include "methods/pt/camera_sample_kernel.glsl"
