// Density estimation from the photon map (Jensen 2001 ch. 7; Hachisuka, Ogaki and Jensen 2008
// for the shrinking radius): the reflected radiance at a shading point,
//   L_r(x, wo) ~ sum_p K(|x - x_p|) f(x, wo, wi_p) Phi_p,
// over the photons p within radius r of x, with a 2D kernel K normalized over the disc.
// The photons sit in a hashed uniform grid of cells of size 2 r (host/methods/pm/photon_map.cpp,
// Teschner et al. 2003's hash), so the sphere of radius r around x meets at most 2 x 2 x 2 cells;
// their buckets are read once each (cells that share a bucket are read once) and the distance
// test drops photons of other cells. A lookup reads at most maxLookup photons (lavapipe's loop
// budget, tests/gpu/test_loop_limits.cpp), maxLookup / 8 per bucket: a fuller bucket is read
// with a stride k from a random offset in [0, k), each photon read standing for k. A bucket
// holds its photons in path order, i.e. in random order, so the strided sum is an unbiased
// estimate of the whole bucket's (every photon is read for exactly one of the k offsets): more
// noise, no bias. Such lookups are counted (COUNTER_PM_LOOKUP_CUT).
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

// The hash of grid cell c (Teschner et al. 2003, "Optimized Spatial Hashing for Collision
// Detection of Deformable Objects"), masked to a grid's bucket count; the host's
// photonCellBucket is the same function.
uint photonCellHash(ivec3 c) {
    return (uint(c.x) * 73856093u) ^ (uint(c.y) * 19349663u) ^ (uint(c.z) * 83492791u);
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

// The hash of corner c (0..7) of the 2 x 2 x 2 cells from `lo`, masked.
uint photonCornerBucket(ivec3 lo, uint c, uint mask) {
    return photonCellHash(lo + ivec3(c & 1u, (c >> 1) & 1u, (c >> 2) & 1u)) & mask;
}

// Radiance reflected at sh towards sh's wo by the photons within the radius of the caustic map
// (caustic) or the global one, whose flags hold none of `exclude` and whose hit index is at most
// maxHit (a photon at hit h ends a light path of h - 1 bounces, so a gather point whose own path
// has b bounces up to here reads h <= maxDepth - b: the depth limit); u in [0, 1) picks the offset
// of strided buckets. Cells the disc's bounding sphere misses are skipped. A Lambertian surface sums the photons' flux on
// its front side and multiplies by its f once; other BSDFs are evaluated per photon. (Two
// loops, not one with a branch inside: lavapipe runs both sides of a branch under lane masks,
// but a loop whose lanes are all masked off ends at once.)
vec3 photonRadiance(ShadingPoint sh, bool caustic, uint exclude, uint maxHit, float u,
                    inout LookupStats stats) {
    float r = photonMap.radius;
    float r2 = r * r;
    vec3 x = sh.surface.position;
    ivec3 lo = ivec3(floor((x - r) / photonMap.cellSize));
    ivec3 hi = ivec3(floor((x + r) / photonMap.cellSize));
    // (A clear coat or a sheen over the Lambertian makes it another BSDF.)
    bool lambertian = sh.bsdf.wBase >= 1.0 && !sh.bsdf.coated && sh.bsdf.clearcoat <= 0.0 &&
                      !bsdfHasSheen(sh.bsdf);
    vec3 sum = vec3(0.0);
    uint perBucket = max(photonMap.maxLookup / 8u, 1u);
    stats.lookups += 1u;
    bool strided = false;
    uint mask = caustic ? photonMap.causticHashMask : photonMap.hashMask;
    uint cellOffset = caustic ? photonMap.causticCellOffset : 0u;
    for (uint c = 0u; c < 8u; ++c) {
        ivec3 cell = lo + ivec3(c & 1u, (c >> 1) & 1u, (c >> 2) & 1u);
        if (any(greaterThan(cell, hi))) continue;
        vec3 boxMin = vec3(cell) * photonMap.cellSize;
        vec3 nearest = clamp(x, boxMin, boxMin + photonMap.cellSize);
        if (dot(nearest - x, nearest - x) > r2) continue;
        // Cells that share a bucket: read it once, at the first of them.
        uint bucket = photonCellHash(cell) & mask;
        bool again = false;
        for (uint k = 0u; k < c; ++k) again = again || photonCornerBucket(lo, k, mask) == bucket;
        if (again) continue;
        uvec2 range = cells[cellOffset + bucket];
        uint stride = (range.y + perBucket - 1u) / perBucket;
        uint offset = 0u;
        float weight = 1.0;
        if (stride > 1u) {
            strided = true;
            offset = min(uint(u * float(stride)), stride - 1u);
            weight = float(stride);
        }
        uint count = range.y > offset ? (range.y - offset + stride - 1u) / stride : 0u;
        uint first = range.x + offset;
        stats.visited += count;
        vec3 bucketSum = vec3(0.0);
        if (lambertian) {
            for (uint k = 0u; k < count; ++k) {
                uint i = first + k * stride;
                vec3 d = photons[i].position - x;
                float d2 = dot(d, d);
                uint flags = photons[i].flags;
                bool skip = (flags & exclude) != 0u || (flags >> PHOTON_HIT_SHIFT) > maxHit;
                if (!(d2 < r2) || skip) continue;
                vec3 wi = octDecode(unpackSnorm2x16(photons[i].direction));
                // shadingEval's side checks: wi above both the geometric and the shading normal.
                if (!(dot(wi, sh.ng) > 0.0) || !(dot(wi, sh.frame.n) > 0.0)) continue;
                stats.used += 1u;
                bucketSum += photonKernel(d2, r2) * photons[i].power;
            }
        } else {
            for (uint k = 0u; k < count; ++k) {
                uint i = first + k * stride;
                vec3 d = photons[i].position - x;
                float d2 = dot(d, d);
                uint flags = photons[i].flags;
                bool skip = (flags & exclude) != 0u || (flags >> PHOTON_HIT_SHIFT) > maxHit;
                if (!(d2 < r2) || skip) continue;
                stats.used += 1u;
                vec3 wi = octDecode(unpackSnorm2x16(photons[i].direction));
                float pdf, absCos;
                vec3 f = shadingEval(sh, wi, pdf, absCos);
                bucketSum += photonKernel(d2, r2) * f * photons[i].power;
            }
        }
        sum += weight * bucketSum;
    }
    if (strided) stats.cut += 1u;
    // Lambertian: f = baseColor / pi (bsdf.glsl bsdfEval's base lobe, weight 1, uncoated).
    if (lambertian) sum *= sh.woLocal.z > 0.0 ? sh.bsdf.baseColor * INV_PI : vec3(0.0);
    return sum / (PI * r2);
}

void lookupStatsCount(LookupStats stats) {
    counterAdd(COUNTER_PM_LOOKUPS, stats.lookups);
    counterAdd(COUNTER_PM_PHOTONS_VISITED, stats.visited);
    counterAdd(COUNTER_PM_PHOTONS_USED, stats.used);
    counterAdd(COUNTER_PM_LOOKUP_CUT, stats.cut);
}

#endif
