#version 460
// PMC-HI adaptive direct lighting: the emission seen at the first hit plus a PMC-HI estimate of
// the light reflected there (shaders/common/pmc_hi.glsl), per camera sample.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock {
    PtPush push;
    PmcHiParams hi;
};

#include "common/film.glsl"
#include "common/camera.glsl"
#include "common/pmc_hi.glsl"

// Per pixel: sums of the final alpha of its first-hit estimates, and their number. Written only
// with PT_SOURCE_TILE (one invocation per pixel per dispatch). The feedback buffers are used
// with request lists (pmc-ip-hi).
layout(set = WORK_SET, binding = PMC_HI_BINDING_ALPHA, scalar) buffer AlphaBuffer {
    float alphaSums[];
};

layout(set = WORK_SET, binding = PMC_HI_BINDING_ALPHA_START, scalar) readonly buffer AlphaStartBuffer {
    float alphaStart[];
};
layout(set = WORK_SET, binding = PMC_HI_BINDING_ALPHA_OUT, scalar) writeonly buffer AlphaOutBuffer {
    float alphaOut[];
};

vec3 estimateRadiance(vec2 raster, inout Sampler smp, inout uint rays, uint recordIndex) {
    const bool feedback = (hi.flags & PMC_HI_FLAG_FEEDBACK) != 0u;
    vec3 dir = cameraDirection(raster);
    Hit hit;
    rays += 1u;
    if (!traceClosest(sceneInfo.cameraPosition, dir, FLOAT_MAX, hit)) {
        if (feedback)
            for (uint k = 0u; k < PMC_HI_MAX_COMPONENTS; ++k) alphaOut[recordIndex * PMC_HI_MAX_COMPONENTS + k] = 0.0;
        return vec3(0.0);
    }
    SurfacePoint s = surfaceAt(hit.triangle, vec2(hit.b1, hit.b2));
    ShadingPoint sh = makeShadingPoint(s, -dir);
    uint pixel = uint(raster.y) * sceneInfo.width + uint(raster.x);
    float start[PMC_HI_MAX_COMPONENTS];
    float startSum = 0.0;
    for (uint k = 0u; k < PMC_HI_MAX_COMPONENTS; ++k) {
        start[k] = feedback ? alphaStart[pixel * PMC_HI_MAX_COMPONENTS + k] : 0.0;
        startSum += start[k];
    }
    float alpha[PMC_HI_MAX_COMPONENTS];
    bool adapted;
    vec3 L = emittedRadiance(s, -dir) +
             pmcHiEstimate(sh, hi, start, startSum > 0.0, smp, rays, alpha, adapted);
    if (feedback) {
        for (uint k = 0u; k < PMC_HI_MAX_COMPONENTS; ++k)
            alphaOut[recordIndex * PMC_HI_MAX_COMPONENTS + k] = adapted ? alpha[k] : 0.0;
    }
    if ((hi.flags & PMC_HI_FLAG_RECORD_ALPHA) != 0u && adapted) {
        uint base = pixel * PMC_HI_ALPHA_STRIDE;
        for (uint k = 0u; k < PMC_HI_MAX_COMPONENTS; ++k) alphaSums[base + k] += alpha[k];
        alphaSums[base + PMC_HI_MAX_COMPONENTS] += 1.0;
    }
    return L;
}

#include "common/camera_sample_kernel.glsl"
