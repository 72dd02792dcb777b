// Path tracing that also writes each sample's path record (ERPT and PMC-ER seeds).
//
// The body of pt_record.comp and pt_record_all_lights.comp (PMCR_OTHER_LIGHTS: punctual
// lights and the environment compiled in); the host picks the variant by the scene's lights
// (lightsKernelVariant, host/methods/pt/pt_integrator.h).
#include "shared/host_device.h"
#define PT_RECORD_PATHS
layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock { PtPush push; };

#include "common/film.glsl"
#include "methods/pt/path_tracer.glsl"

// Paths in turn from pathBegin / pathBounce / pathEnd (camera_sample_kernel.glsl).
#define CAMERA_SAMPLE_PATH_STATES
#include "methods/pt/camera_sample_kernel.glsl"
