// The body of pmc_hi.comp and pmc_hi_all_lights.comp. PMC-HI adaptive direct lighting: the
// emission seen at the first hit plus a PMC-HI estimate of the light reflected there
// (pmc_hi.glsl), plus with punctual lights their separate next-event estimate, per camera sample;
// a camera ray that escapes sees the environment. The host picks the variant by the scene's
// lights (pmcHiKernel, host/methods/pmc_hi/pmc_hi.h).
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock {
    PtPush push;
    PmcHiParams hi;
};

#include "common/film.glsl"
#include "common/camera.glsl"
#include "methods/pmc_hi/pmc_hi.glsl"

// Per pixel: sums of the final alpha of its first-hit estimates, and their number. Written only
// with PT_SOURCE_TILE (one invocation per pixel per dispatch). The feedback buffers are used
// with request lists (pmc-ip-hi).
layout(set = WORK_SET, binding = PMC_HI_BINDING_ALPHA, scalar) buffer AlphaBuffer {
    float alphaSums[];
};

#include "methods/pmc_hi/pmc_hi_feedback.glsl"

// The feedback and alpha-map loops run over the m slots in use, not all PMC_HI_MAX_COMPONENTS,
// and stay loops ([[dont_unroll]]): lavapipe runs both sides of every branch under lane masks, so
// unrolled they would cost every camera sample a load or store per slot (each a loop over the
// lanes) even with their flag off.
vec3 estimateRadiance(vec2 raster, inout Sampler smp, inout uint rays, uint recordIndex) {
    const uint m = pmcHiSlots(hi);  // slots in use
    const uint feedbackSlots = (hi.flags & PMC_HI_FLAG_FEEDBACK) != 0u ? m : 0u;
    const uint recordSlots = (hi.flags & PMC_HI_FLAG_RECORD_ALPHA) != 0u ? m : 0u;
    vec3 dir = cameraDirection(raster);
    Hit hit;
    rays += 1u;
    bool found = traceClosest(sceneInfo.cameraPosition, dir, FLOAT_MAX, hit);
    SurfacePoint s = surfaceAt(found ? hit.triangle : 0u, vec2(hit.b1, hit.b2));
    ShadingPoint sh = makeShadingPoint(s, -dir);
    uint pixel = uint(raster.y) * sceneInfo.width + uint(raster.x);
    float start[PMC_HI_MAX_COMPONENTS];
    float startSum = pmcHiStartingAlpha(pixel, feedbackSlots, start);
    float alpha[PMC_HI_MAX_COMPONENTS];
    bool adapted = false;
    vec3 L = vec3(0.0);
    if (found) {
        L = emittedRadiance(s, -dir) +
            pmcHiEstimate(sh, hi, start, startSum > 0.0, smp, rays, alpha, adapted);
        if (hasPunctualLights()) L += pmcHiPunctualDirect(sh, samplerGet1D(smp), rays);
        L *= segmentTransmittance(s, dir, hit.t);  // a camera inside absorbing glass
    } else if (hasEnvironment()) {
        L = envRadiance(dir);  // seen by the camera: no estimate to weigh it against
    }
    pmcHiWriteFinalAlpha(recordIndex, feedbackSlots, adapted, alpha);
    if (adapted) {
        uint base = pixel * PMC_HI_ALPHA_STRIDE;
        [[dont_unroll]] for (uint k = 0u; k < recordSlots; ++k) alphaSums[base + k] += alpha[k];
        if (recordSlots > 0u) alphaSums[base + PMC_HI_MAX_COMPONENTS] += 1.0;
    }
    return L;
}

#include "methods/pt/camera_sample_kernel.glsl"
