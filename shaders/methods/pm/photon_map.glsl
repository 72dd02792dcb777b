// Density estimation from the photon map (Jensen 2001 ch. 7; Hachisuka, Ogaki and Jensen 2008
// for the shrinking radius): the reflected radiance at a shading point,
//   L_r(x, wo) ~ sum_p K(|x - x_p|) f(x, wo, wi_p) Phi_p,
// over the photons p within radius r of x, with a 2D kernel K normalized over the disc.
// The photons sit in a hashed uniform grid of cells of size 2 r (host/methods/pm/photon_map.cpp,
// Teschner et al. 2003's hash), so the sphere of radius r around x meets at most 2 x 2 x 2 cells;
// their buckets are read once each (cells that share a bucket are read once) and the distance
// test drops photons of other cells. A lookup reads at most maxLookup photons (lavapipe's loop
// budget, tests/gpu/test_loop_limits.cpp): a lookup cut short is counted (COUNTER_PM_LOOKUP_CUT).
#ifndef PMCR_PHOTON_MAP_GLSL
#define PMCR_PHOTON_MAP_GLSL

#include "common/octahedral.glsl"
#include "common/shading.glsl"

layout(set = WORK_SET, binding = PM_BINDING_PHOTONS, scalar) readonly buffer PhotonBuffer {
    Photon photons[];
};
layout(set = WORK_SET, binding = PM_BINDING_CELLS, scalar) readonly buffer CellBuffer {
    uvec2 cells[];  // (first photon, count) per bucket
};
layout(set = WORK_SET, binding = PM_BINDING_INFO, scalar) readonly buffer PhotonInfoBuffer {
    PhotonMapInfo photonMap;
};

// The bucket of grid cell c (Teschner et al. 2003, "Optimized Spatial Hashing for Collision
// Detection of Deformable Objects"); the host's photonCellBucket is the same function.
uint photonCellBucket(ivec3 c) {
    return ((uint(c.x) * 73856093u) ^ (uint(c.y) * 19349663u) ^ (uint(c.z) * 83492791u)) &
           photonMap.hashMask;
}

// The kernel's weight at squared distance d2 < r2, times pi r^2 (the caller divides by it).
float photonKernel(float d2, float r2) {
    if (photonMap.kernel == PM_KERNEL_EPANECHNIKOV) return 2.0 * (1.0 - d2 / r2);
    if (photonMap.kernel == PM_KERNEL_CONE) return 3.0 * (1.0 - sqrt(d2 / r2));
    return 1.0;
}

// Statistics of the lookups of one invocation, for the counters.
struct LookupStats {
    uint lookups;
    uint visited;
    uint used;
    uint cut;
};

LookupStats lookupStatsCreate() { return LookupStats(0u, 0u, 0u, 0u); }

// Radiance reflected at sh towards sh's wo by the photons within the radius whose flags hold
// every bit of `require` and none of `exclude`.
vec3 photonRadiance(ShadingPoint sh, uint require, uint exclude, inout LookupStats stats) {
    float r = photonMap.radius;
    float r2 = r * r;
    vec3 x = sh.surface.position;
    ivec3 lo = ivec3(floor((x - r) / photonMap.cellSize));
    ivec3 hi = ivec3(floor((x + r) / photonMap.cellSize));
    vec3 sum = vec3(0.0);
    uint budget = photonMap.maxLookup;
    uint seen[8];
    uint seenCount = 0u;
    stats.lookups += 1u;
    for (uint c = 0u; c < 8u; ++c) {
        ivec3 cell = lo + ivec3(c & 1u, (c >> 1) & 1u, (c >> 2) & 1u);
        if (any(greaterThan(cell, hi))) continue;
        uint bucket = photonCellBucket(cell);
        bool again = false;
        for (uint k = 0u; k < seenCount; ++k) again = again || seen[k] == bucket;
        if (again) continue;
        seen[seenCount] = bucket;
        seenCount += 1u;
        uvec2 range = cells[bucket];
        uint count = min(range.y, budget);
        if (count < range.y) stats.cut += 1u;
        budget -= count;
        stats.visited += count;
        for (uint k = 0u; k < count; ++k) {
            Photon p = photons[range.x + k];
            vec3 d = p.position - x;
            float d2 = dot(d, d);
            if (!(d2 < r2) || (p.flags & require) != require || (p.flags & exclude) != 0u) continue;
            stats.used += 1u;
            vec3 wi = octDecode(unpackSnorm2x16(p.direction));
            float pdf, absCos;
            vec3 f = shadingEval(sh, wi, pdf, absCos);
            sum += photonKernel(d2, r2) * f * p.power;
        }
    }
    return sum / (PI * r2);
}

void lookupStatsCount(LookupStats stats) {
    counterAdd(COUNTER_PM_LOOKUPS, stats.lookups);
    counterAdd(COUNTER_PM_PHOTONS_VISITED, stats.visited);
    counterAdd(COUNTER_PM_PHOTONS_USED, stats.used);
    counterAdd(COUNTER_PM_LOOKUP_CUT, stats.cut);
}

#endif
