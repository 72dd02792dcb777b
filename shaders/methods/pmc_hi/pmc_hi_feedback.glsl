// PMC-IP's feedback to PMC-HI (Fan et al. sec. 6.1) on the kernel side, for the kernels that
// estimate direct light with PMC-HI at one point per camera sample (pmc_hi_kernel.glsl, and
// photon mapping's gather, methods/pm/pm_gather_kernel.glsl): per pixel the starting alpha the
// host's auxiliary image holds, per request the final alpha of its estimate. The loops run over
// the `slots` in use (0 without feedback) and stay loops ([[dont_unroll]]: the includer enables
// GL_EXT_control_flow_attributes): lavapipe runs both sides of every branch under lane masks, so
// unrolled they would cost every camera sample a load or store per slot even with feedback off.
#ifndef PMCR_PMC_HI_FEEDBACK_GLSL
#define PMCR_PMC_HI_FEEDBACK_GLSL

layout(set = WORK_SET, binding = PMC_HI_BINDING_ALPHA_START, scalar) readonly buffer AlphaStartBuffer {
    float alphaStart[];
};
layout(set = WORK_SET, binding = PMC_HI_BINDING_ALPHA_OUT, scalar) writeonly buffer AlphaOutBuffer {
    float alphaOut[];
};

// `pixel`'s starting alpha in its first `slots` components (the rest 0); returns their sum
// (0: none yet).
float pmcHiStartingAlpha(uint pixel, uint slots, out float start[PMC_HI_MAX_COMPONENTS]) {
    float sum = 0.0;
    for (uint k = 0u; k < PMC_HI_MAX_COMPONENTS; ++k) start[k] = 0.0;
    [[dont_unroll]] for (uint k = 0u; k < slots; ++k) {
        start[k] = alphaStart[pixel * PMC_HI_MAX_COMPONENTS + k];
        sum += start[k];
    }
    return sum;
}

// Request `request`'s final alpha; all 0 when nothing was adapted (a miss, a delta BSDF).
void pmcHiWriteFinalAlpha(uint request, uint slots, bool adapted, float alpha[PMC_HI_MAX_COMPONENTS]) {
    [[dont_unroll]] for (uint k = 0u; k < slots; ++k)
        alphaOut[request * PMC_HI_MAX_COMPONENTS + k] = adapted ? alpha[k] : 0.0;
}

#endif
