// The body of direct.comp and direct_all_lights.comp (MIS direct lighting). The host picks the
// variant by the scene's lights (pathTracingKernel, host/methods/pt/pt_integrator.h).
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock { PtPush push; };

#include "common/film.glsl"
#include "methods/pt/path_tracer.glsl"

vec3 estimateRadiance(vec2 raster, inout Sampler s, inout uint rays, uint recordIndex) {
    return directLighting(raster, s, push.lightSamples, rays);
}

#include "methods/pt/camera_sample_kernel.glsl"
