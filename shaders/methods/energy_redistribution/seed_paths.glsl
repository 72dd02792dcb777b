// Seed paths of energy redistribution (ERPT, PMC-ER): the light paths of a path-traced sample.
// A PathRecord (shared/path_types.h) of k eye vertices holds up to 2k light paths: for every
// vertex x_j, the implicit path x1..x_j when x_j is an emitter hit, and the explicit path
// x1..x_j y_j when light sampling connected x_j to y_j. Seed path s of a record is
// (vertex j = s / 2, kind = s % 2: 0 implicit, 1 explicit). With punctual lights and the
// environment (kernels compiled with PMCR_OTHER_LIGHTS), explicit connections to them and rays
// that escape to the environment are seed paths too (shared/path_types.h), so the seeds carry
// every term of the path tracer's estimate.
#ifndef PMCR_SEED_PATHS_GLSL
#define PMCR_SEED_PATHS_GLSL

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
// own pixel (erpt_count, pmc_er_seed) instead of starting chains or population members. The
// pixel's estimate is the sum over its seed paths of their contributions; each term is estimated without bias either way (the seed
// itself, or the chains it starts, ERPT sec. 3.2), so the sum stays unbiased. Path tracing with
// light sampling already estimates these terms with little noise, which chains would only add.
bool isDirectSeed(uint s) { return s < 3u; }

#ifdef PMCR_PATH_SPACE_GLSL
// Copies seed path s of record `rec` (x1..x_j, + the light point) into slot 0 of `chain` and
// returns the chain's state; the caller sets rng and origin.
ChainState chainFromSeedPath(uint chain, PathRecord rec, uint s) {
    uint base = pathBase(chain, 0u);
    uint j = s / 2u;
    bool explicitPath = (s & 1u) == 1u;
    for (uint v = 0u; v <= j; ++v) {
        PathVertex pv = recordVertices[rec.firstVertex + v];
        uint flags = 0u;
        if (v < j) {
            flags = pv.flags & (VERTEX_SPECULAR | VERTEX_TRANSMISSION);
            if ((pv.flags & VERTEX_SPECULAR) != 0u) flags |= pv.lobe << CHAIN_LOBE_SHIFT;
        } else if (!explicitPath) {
            flags = VERTEX_EMITTER | (pv.flags & VERTEX_ENVIRONMENT);
        }
        chainVertices[base + v] = makeChainVertex(pv.triangle, pv.barycentrics, flags);
    }
    uint k = j + 1u;
    if (explicitPath) {
        PathVertex pv = recordVertices[rec.firstVertex + j];
        uint flags = VERTEX_EMITTER;
        if ((pv.flags & VERTEX_SAMPLED_PUNCTUAL) != 0u) flags |= VERTEX_PUNCTUAL;
        if ((pv.flags & VERTEX_SAMPLED_ENVIRONMENT) != 0u) flags |= VERTEX_ENVIRONMENT;
        chainVertices[base + k] = makeChainVertex(pv.lightTriangle, vec2(pv.lightB1, pv.lightB2), flags);
        k += 1u;
    }
    ChainState st;
    st.raster = rec.raster;
    st.vertexCount = k;
    st.slot = 0u;
    st.throughput = pathThroughput(base, k);
    st.rng = 0u;
    st.lastPixel = 0xffffffffu;
    st.consecutive = 0u;
    st.origin = 0u;
    st.pad = 0u;
    return st;
}
#endif

#endif
