// MLT: the bootstrap and the chains' start (Veach 1997 sec. 11.3.1). Without MLT_FLAG_START,
// invocation i draws bootstrap sample push.chainBase + i with the independent sampler
// (independent_path.glsl) in chain slot i's vertices (scratch) and writes its weight lum(W).
// With it, chain push.chainBase + i redraws the sample `starts` names (the same random numbers,
// so the same path, bit for bit) into its slot 0 and becomes that path's chain.
//
// The body of mlt_seed.comp and mlt_seed_all_lights.comp (PMCR_OTHER_LIGHTS: punctual lights and
// the environment compiled in).
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock { MltPush push; };
#define FILM_BINDING ERPT_BINDING_SPLAT
#define COUNTERS_BINDING ERPT_BINDING_COUNTERS
#include "common/film.glsl"
#include "methods/mlt/independent_path.glsl"

layout(set = WORK_SET, binding = ERPT_BINDING_CHAINS, scalar) writeonly buffer ChainBuffer { ChainState chains[]; };
layout(set = WORK_SET, binding = ERPT_BINDING_PIXEL_STATS, scalar) buffer PixelStatsBuffer {
    PixelChainStats pixelStats[];
};
layout(set = WORK_SET, binding = MLT_BINDING_WEIGHTS, scalar) writeonly buffer WeightBuffer { float weights[]; };
layout(set = WORK_SET, binding = MLT_BINDING_STARTS, scalar) readonly buffer StartBuffer { uint starts[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint rays = 0u;
    if (i < push.chainCount) {
        bool start = (push.flags & MLT_FLAG_START) != 0u;
        uint chain = start ? push.chainBase + i : i;
        uint sampleIndex = start ? starts[chain] : push.chainBase + i;
        Rng rng = rngCreate(hash3(push.seed ^ 0x6d6c7462u, sampleIndex, 0u));
        uint base = pathBase(chain, 0u);
        vec2 raster;
        uint k;
        vec3 P = vec3(0.0);
        float w = 0.0;
        if (sampleIndependentPath(base, push.maxDepth, rng, rays, raster, k) && k >= push.minVertices)
            w = luminance(independentWeight(base, k, push.maxDepth, P));
        if (!start) {
            weights[sampleIndex] = isFinite(w) && w > 0.0 ? w : 0.0;
        } else {
            ChainState st;
            st.raster = raster;
            st.vertexCount = k;
            st.slot = 0u;
            st.throughput = P;
            st.rng = hash3(push.seed ^ 0x6d6c7463u, chain, 1u);
            st.lastPixel = 0xffffffffu;
            st.consecutive = 0u;
            st.origin = sampleIndex;
            st.pad = 0u;
            chains[chain] = st;
            atomicAdd(pixelStats[rasterPixel(raster)].chainsStarted, 1u);
        }
    }
    counterAdd(COUNTER_RAYS, rays);
}
