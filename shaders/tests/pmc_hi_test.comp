#version 460
// Test kernel for shaders/methods/pmc_hi/pmc_hi.glsl (tests/gpu/test_pmc_hi.cpp), on the bound
// scene and the mixture in `setup`. u's come from rngCreate(hashCombine(i, seed)).
//   mode 0: pmcHiAllocate(alpha, m, N, u = (i + 1/2) / count): results[3i .. 3i+2] = counts of
//           slots 0..11
//   mode 1: component k drawn with probability alpha_k, then pmcHiDrawDirection:
//           results[i] = (wi, 0 failed | 1 non-delta | 2 delta)
//   mode 2: direction directions[i]: results[i] = (mixture density K, cone density, the
//           environment component's a_env envPdf when the ray hits a surface, 0), the light
//           densities at the first hit of the ray from the shading point. K is the density of
//           the directions that score; the environment's draws that hit a surface score 0, so
//           what the mixture draws has the density K + the third value.
// Compiled with the environment (PMCR_OTHER_LIGHTS): hasEnvironment() follows the bound scene.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#define PMCR_OTHER_LIGHTS
#include "shared/host_device.h"

#include "methods/pmc_hi/pmc_hi.glsl"
#include "common/rng.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(set = WORK_SET, binding = 0, scalar) writeonly buffer Results { vec4 results[]; };
layout(set = WORK_SET, binding = 1, scalar) readonly buffer Setup { PmcHiTestSetup setup; };
layout(set = WORK_SET, binding = 2, scalar) readonly buffer Directions { vec4 directions[]; };
layout(push_constant, scalar) uniform Push {
    uint mode;
    uint count;
    uint seed;
} push;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    Rng rng = rngCreate(hashCombine(i, push.seed));
    PmcHiKernel kern;
    kern.alpha = setup.alpha;
    kern.coneAxis = setup.coneAxis;
    kern.coneOneMinusCos = setup.coneOneMinusCos;

    if (push.mode == 0u) {
        uint counts[PMC_HI_MAX_COMPONENTS];
        pmcHiAllocate(kern.alpha, setup.m, setup.N, (float(i) + 0.5) / float(push.count), counts);
        float c[12];
        for (uint k = 0u; k < 12u; ++k) c[k] = k < PMC_HI_MAX_COMPONENTS ? float(counts[k]) : 0.0;
        results[3u * i] = vec4(c[0], c[1], c[2], c[3]);
        results[3u * i + 1u] = vec4(c[4], c[5], c[6], c[7]);
        results[3u * i + 2u] = vec4(c[8], c[9], c[10], c[11]);
        return;
    }

    SurfacePoint s = surfaceAt(setup.triangle, setup.barycentrics);
    ShadingPoint sh = makeShadingPoint(s, setup.wo);
    if (push.mode == 1u) {
        float uComponent = rngNext(rng);
        uint k = 0u;
        float cdf = 0.0;
        for (uint j = 0u; j < PMC_HI_MAX_COMPONENTS; ++j) {
            if (kern.alpha[j] <= 0.0) continue;
            k = j;
            cdf += kern.alpha[j];
            if (uComponent < cdf) break;
        }
        float u1 = rngNext(rng);
        vec2 u2 = rngNext2(rng);
        PmcHiDraw d;
        bool drawn = pmcHiDrawDirection(sh, setup.params, k, kern, u1, u2, d);
        results[i] = vec4(d.wi, !drawn ? 0.0 : d.delta ? 2.0 : 1.0);
        return;
    }

    vec3 wi = normalize(directions[i].xyz);
    float pdfBsdf, absCos;
    shadingEval(sh, wi, pdfBsdf, absCos);
    Hit hit;
    bool hitSomething = traceClosest(spawnOrigin(sh, wi), wi, FLOAT_MAX, hit);
    SurfacePoint l = s;
    if (hitSomething) l = surfaceAt(hit.triangle, vec2(hit.b1, hit.b2));
    float K = pmcHiDensity(setup.params, kern, s.position, wi, pdfBsdf, hitSomething, l,
                           PMC_HI_MAX_COMPONENTS);
    float envUnscored = hitSomething && pmcHiHasEnvironment(setup.params)
                            ? kern.alpha[pmcHiEnvironmentSlot(setup.params)] * envPdf(wi) : 0.0;
    results[i] = vec4(K, pmcHiConePdf(kern.coneAxis, kern.coneOneMinusCos, wi), envUnscored, 0.0);
}
