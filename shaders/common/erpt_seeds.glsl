// ERPT's seeds: the light paths of a path-traced sample and how many chains each starts.
// A PathRecord (shared/path_types.h) of k eye vertices holds up to 2k light paths: for every
// vertex x_j, the implicit path x1..x_j when x_j is an emitter hit, and the explicit path
// x1..x_j y_j when light sampling connected x_j to y_j. Seed path s of a record is
// (vertex j = s / 2, kind = s % 2: 0 implicit, 1 explicit).
//
// Equal deposition (ERPT fig. 6): a path of energy e starts numChains = floor(U + e / (m e_d))
// chains of m mutations, each depositing e_d per mutation; E[numChains m e_d] = e, unbiased.
#ifndef PMCR_ERPT_SEEDS_GLSL
#define PMCR_ERPT_SEEDS_GLSL

#include "common/rng.glsl"

layout(set = WORK_SET, binding = ERPT_BINDING_RECORDS, scalar) readonly buffer RecordBuffer {
    PathRecord records[];
};
layout(set = WORK_SET, binding = ERPT_BINDING_RECORD_VERTICES, scalar) readonly buffer RecordVertexBuffer {
    PathVertex recordVertices[];
};

vec3 seedContribution(PathRecord rec, uint s) {
    PathVertex v = recordVertices[rec.firstVertex + s / 2u];
    if ((s & 1u) == 0u)
        return (v.flags & VERTEX_EMITTER) != 0u ? v.implicitContribution : vec3(0.0);
    return (v.flags & VERTEX_HAS_LIGHT_SAMPLE) != 0u ? v.explicitContribution : vec3(0.0);
}

// Seed paths with at most one scattering vertex between the eye and the light: the emitter seen
// directly (s = 0) and direct lighting at the first hit (s = 1: light sampling; s = 2: the
// BSDF-sampled ray hit an emitter). With ERPT_FLAG_DEPOSIT_DIRECT these are deposited at their
// own pixel by erpt_count instead of starting chains. The pixel's estimate is the sum over its
// seed paths of their contributions; each term is estimated without bias either way (the seed
// itself, or the chains it starts, ERPT sec. 3.2), so the sum stays unbiased. Path tracing with
// light sampling already estimates these terms with little noise, which chains would only add.
bool isDirectSeed(uint s) { return s < 3u; }

// Chains started by seed path s of record r; the random number comes from (seed, pass, r, s)
// so that the counting and the writing kernels agree.
uint seedChainCount(PathRecord rec, uint r, uint s) {
    vec3 c = seedContribution(rec, s);
    float e = luminance(c) * push.seedScale;
    if (!(e > 0.0) || !isFinite(c)) return 0u;
    if ((push.flags & ERPT_FLAG_DEPOSIT_DIRECT) != 0u && isDirectSeed(s)) return 0u;
    Rng rng = rngCreate(hash3(push.seed ^ 0x5eedc4a1u, push.pass, r * (2u * PATH_MAX_VERTICES) + s));
    float chains = floor(rngNext(rng) + e / (float(push.chainLength) * push.depositEnergy));
    return uint(min(chains, 4.0e9));
}

#endif
