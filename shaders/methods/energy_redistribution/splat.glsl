// Deposits of energy redistribution: 64-bit fixed point per channel, SPLAT_QUANTA_PER_DEPOSIT
// quanta per e_d, rounded stochastically (so the expected sum is exact: unbiased) with the
// chain's own random numbers (so the same seed gives the same sums). Integer atomics commute,
// so the image does not depend on the order in which chains deposit.
#ifndef PMCR_SPLAT_GLSL
#define PMCR_SPLAT_GLSL

#extension GL_EXT_shader_atomic_int64 : require

#include "common/rng.glsl"

layout(set = WORK_SET, binding = ERPT_BINDING_SPLAT, scalar) buffer SplatBuffer { SplatPixel splat[]; };

// Adds `amount` deposits of colour `rgb` (luminance 1: one deposit carries e_d of luminance) to
// `pixel`. Returns false, adding nothing, for non-finite values.
bool splatDeposit(uint pixel, vec3 rgb, float amount, inout Rng rng) {
    vec3 q = rgb * (amount * SPLAT_QUANTA_PER_DEPOSIT);
    if (!isFinite(q) || any(lessThan(q, vec3(0.0))) || maxComponent(q) > 4.0e15) return false;
    vec3 rounded = floor(q + vec3(rngNext(rng), rngNext(rng), rngNext(rng)));
    if (rounded.x > 0.0) atomicAdd(splat[pixel].r, uint64_t(rounded.x));
    if (rounded.y > 0.0) atomicAdd(splat[pixel].g, uint64_t(rounded.y));
    if (rounded.z > 0.0) atomicAdd(splat[pixel].b, uint64_t(rounded.z));
    return true;
}

#endif
