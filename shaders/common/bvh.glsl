// BVH traversal used by every kernel: closest hit and any hit on the binary BVH that
// host/scene/bvh.cpp builds. The arithmetic (intersection tests, epsilon policy, traversal
// order) is that of Bvh::traceClosest / Bvh::traceAny; see host/scene/bvh.h for the policy:
// Moller-Trumbore with a division-free inside test and inclusive edges, hits with
// 0 < t < tMax, no self-intersection epsilon (offset origins in the caller).
//
// The BVH is one uniform texel buffer of uvec4 (Bvh::deviceTexels, layout in
// shared/scene_types.h): node i is texels 2i (boundsMin, ref) and 2i + 1 (boundsMax, count),
// where ref is the texel address of the first child's record (interior, count == 0) or of the
// first triangle (leaf); a triangle is three texels (v0 + original index, e1, e2).
//
// Written for SIMD-on-CPU implementations (lavapipe runs 8 invocations as the lanes of one
// vector, both sides of a divergent branch under masks), where memory reads dominate: a texel
// fetch is a vector gather, while an SSBO load with per-lane addresses is a loop over the
// lanes. So each traversal step is one "if-if" step (Aila & Laine 2009, "Understanding the
// Efficiency of Ray Traversal on GPUs") that does the same four texel fetches in every lane,
// whatever the lane is doing: the two child records of an interior node (4 texels), or one
// triangle of a leaf (3 texels). The box and the triangle arithmetic are cheap next to them.
//
// Bounds: the stack holds BVH_MAX_DEPTH node references (near child first pushes at most one
// sibling per level, and the builder caps leaf depth at BVH_MAX_DEPTH); each step visits one
// interior node or one triangle and none twice, so the loop runs fewer than
// textureSize(bvhTexels) times.
#ifndef PMCR_COMMON_BVH_GLSL
#define PMCR_COMMON_BVH_GLSL

layout(set = SCENE_SET, binding = BINDING_BVH) uniform usamplerBuffer bvhTexels;

uvec4 bvhTexel(uint i) { return texelFetch(bvhTexels, int(i)); }

#ifdef BVH_COUNT_STEPS
// Diagnostics only (shaders/bench/trace_rays_steps.comp): the steps of the last traversal.
uint bvhInteriorSteps = 0u;
uint bvhTriangleSteps = 0u;
#endif

// Reciprocal direction with tiny components clamped to +-BVH_MIN_DIRECTION (-0 taken as +).
vec3 bvhSafeInverse(vec3 dir) {
    vec3 d;
    for (int i = 0; i < 3; ++i) {
        d[i] = abs(dir[i]) < BVH_MIN_DIRECTION
                   ? (dir[i] < 0.0 ? -BVH_MIN_DIRECTION : BVH_MIN_DIRECTION)
                   : dir[i];
    }
    return 1.0 / d;
}

// Slab test (Kay & Kajiya 1986) against [0, tMax]; tNear is the entry distance, clamped to 0.
// The exit distance is scaled by 1 + 2 gamma(3) (pbrt-v4 Bounds3::IntersectP).
bool bvhIntersectBox(vec3 boundsMin, vec3 boundsMax, vec3 origin, vec3 invDir, float tMax,
                     out float tNear) {
    vec3 t0 = (boundsMin - origin) * invDir;
    vec3 t1 = (boundsMax - origin) * invDir;
    vec3 tMinV = min(t0, t1);
    vec3 tMaxV = max(t0, t1);
    tNear = max(max(tMinV.x, tMinV.y), max(tMinV.z, 0.0));
    float tFar = min(min(min(tMaxV.x, tMaxV.y), tMaxV.z) * BVH_BOX_EXIT_SCALE, tMax);
    return tNear <= tFar;
}

// Moller & Trumbore 1997 with the inside test on numerators scaled by |det|; on a hit with
// 0 < t < hit.t overwrites hit. Same operations as intersectTriangle() in host/scene/bvh.h.
// v0.w holds the original triangle index (as float bits).
// e1.w and e2.w mark an alpha-masked triangle (shared/scene_types.h IsectTriangle): with the
// scene.glsl kernels of a scene that has alpha masks (sceneHasAlphaMasks), a hit where its mask
// cuts the surface away is no hit, for closest-hit and any-hit rays alike.
bool bvhIntersectTriangle(vec4 v0, vec4 e1, vec4 e2, vec3 origin, vec3 dir, inout Hit hit) {
    vec3 p = cross(dir, e2.xyz);
    float det = dot(e1.xyz, p);
    float sgn = det < 0.0 ? -1.0 : 1.0;
    float absDet = det * sgn;
    vec3 s = origin - v0.xyz;
    float u = dot(s, p) * sgn;
    vec3 q = cross(s, e1.xyz);
    float v = dot(dir, q) * sgn;
    float invDet = 1.0 / absDet;
    float t = dot(e2.xyz, q) * sgn * invDet;
    // One test of everything (no early outs: on SIMD lanes every branch costs mask work).
    bool inside = absDet > 0.0 && u >= 0.0 && u <= absDet && v >= 0.0 && u + v <= absDet;
    if (!(inside && t > 0.0 && t < hit.t)) {
        return false;
    }
#ifdef PMCR_SCENE_GLSL
    if (sceneHasAlphaMasks() && floatBitsToUint(e1.w) != 0u &&
        alphaCutAway(floatBitsToUint(e1.w), e2.w, floatBitsToUint(v0.w), u * invDet, v * invDet)) {
        return false;
    }
#endif
    hit = Hit(t, floatBitsToUint(v0.w), u * invDet, v * invDet);
    return true;
}

// The traversal's reference to a node: its ref * 8 + count (count <= BVH_MAX_LEAF_TRIANGLES
// < 8; Bvh::deviceTexels keeps texel addresses below 2^29). Inside a leaf the same form walks
// its triangles: address of the next one * 8 + how many are left.
uint bvhNodeRef(uvec4 lo, uvec4 hi) { return (lo.w << 3) | hi.w; }

// The stack below the traversal's eight register entries: BVH_MAX_DEPTH - 8 entries per
// invocation in workgroup-shared memory (14 KiB for 64 invocations, within Vulkan's 16 KiB
// minimum of maxComputeSharedMemorySize); every kernel that traces has local_size_x =
// WORKGROUP_SIZE. An invocation runs one traversal at a time. On lavapipe pt's kernel samples
// 1.4-1.6x faster with this shared array than with a private uint[BVH_MAX_DEPTH] doing the
// same accesses (three paired runs of bench/throughput, issue 20; images the same bit for
// bit), while the bench's traversal-only kernel runs as fast with either.
shared uint bvhStackSpillShared[WORKGROUP_SIZE * (BVH_MAX_DEPTH - 8u)];
#define bvhStackSpill(i) bvhStackSpillShared[gl_LocalInvocationIndex * (BVH_MAX_DEPTH - 8u) + (i)]

// A traversal in progress: near-child-first, with anyHit it ends at the first hit. bvhBegin
// starts one, each bvhStep takes one step (an interior step tests both child boxes, descends
// into the nearer and pushes the farther; a leaf step tests one triangle), so that a kernel can
// run the steps of several rays in turn in one loop (trace_rays.glsl) as well as one ray's.
struct BvhTraversal {
    vec3 origin;
    vec3 dir;
    vec3 invDir;
    Hit hit;          // the closest hit so far; its t bounds the search
    uint ref;         // the next step's node or triangle (bvhNodeRef)
    uint stackSize;
    // The stack's top eight entries, in registers.
    uint top0;
    uint top1;
    uint top2;
    uint top3;
    uint top4;
    uint top5;
    uint top6;
    uint top7;
    bool anyHit;
    bool found;       // a triangle was hit
};

// Starts the traversal of origin + t dir for hits with 0 < t < tMax. Returns false when the
// ray misses the root box: the traversal has then already ended, with found == false.
bool bvhBegin(vec3 origin, vec3 dir, float tMax, bool anyHit, out BvhTraversal t) {
    t.origin = origin;
    t.dir = dir;
    t.invDir = bvhSafeInverse(dir);
    t.hit = Hit(tMax, BVH_NO_HIT, 0.0, 0.0);
    t.stackSize = 0u;
    t.top0 = 0u;
    t.top1 = 0u;
    t.top2 = 0u;
    t.top3 = 0u;
    t.top4 = 0u;
    t.top5 = 0u;
    t.top6 = 0u;
    t.top7 = 0u;
    t.anyHit = anyHit;
    t.found = false;
    uvec4 rootLo = bvhTexel(0u);
    uvec4 rootHi = bvhTexel(1u);
    t.ref = bvhNodeRef(rootLo, rootHi);
    float tEntry;
    return bvhIntersectBox(uintBitsToFloat(rootLo.xyz), uintBitsToFloat(rootHi.xyz), origin,
                           t.invDir, tMax, tEntry);
}

// One step of traversal t. Returns false when the traversal has ended (t.found and t.hit are
// then final).
bool bvhStep(inout BvhTraversal t) {
    uint count = t.ref & 7u;
    uint address = t.ref >> 3;
#ifdef BVH_COUNT_STEPS
    if (count > 0u) {
        ++bvhTriangleSteps;
    } else {
        ++bvhInteriorSteps;
    }
#endif
    // The same four fetches in every lane: two child records, or a triangle (the fourth
    // fetch repeats its first texel, so it never reads past the last triangle).
    uvec4 w0 = bvhTexel(address);
    uvec4 w1 = bvhTexel(address + 1u);
    uvec4 w2 = bvhTexel(address + 2u);
    uvec4 w3 = bvhTexel(count > 0u ? address : address + 3u);
    bool next = false;  // t.ref is set to the next node or triangle
    if (count > 0u) {
        if (bvhIntersectTriangle(uintBitsToFloat(w0), uintBitsToFloat(w1), uintBitsToFloat(w2),
                                 t.origin, t.dir, t.hit)) {
            t.found = true;
        }
        if (count > 1u) {
            t.ref = ((address + 3u) << 3) | (count - 1u);
            next = true;
        }
    } else {
        float tLeft;
        float tRight;
        bool hitLeft = bvhIntersectBox(uintBitsToFloat(w0.xyz), uintBitsToFloat(w1.xyz),
                                       t.origin, t.invDir, t.hit.t, tLeft);
        bool hitRight = bvhIntersectBox(uintBitsToFloat(w2.xyz), uintBitsToFloat(w3.xyz),
                                        t.origin, t.invDir, t.hit.t, tRight);
        uint leftRef = bvhNodeRef(w0, w1);
        uint rightRef = bvhNodeRef(w2, w3);
        if (hitLeft && hitRight) {
            bool leftFirst = tLeft <= tRight;
            if (t.stackSize < BVH_MAX_DEPTH) {
                if (t.stackSize >= 8u) {
                    bvhStackSpill(t.stackSize - 8u) = t.top7;
                }
                t.top7 = t.top6;
                t.top6 = t.top5;
                t.top5 = t.top4;
                t.top4 = t.top3;
                t.top3 = t.top2;
                t.top2 = t.top1;
                t.top1 = t.top0;
                t.top0 = leftFirst ? rightRef : leftRef;
                ++t.stackSize;
            }
            t.ref = leftFirst ? leftRef : rightRef;
            next = true;
        } else if (hitLeft || hitRight) {
            t.ref = hitLeft ? leftRef : rightRef;
            next = true;
        }
    }
    if (t.anyHit && t.found) {
        return false;
    }
    if (next) {
        return true;
    }
    // Pop the next subtree. Unlike Bvh::traverse, no entry distance is kept to skip subtrees
    // beyond the closest hit when popped: the popped node's children are culled by their boxes
    // in the next step anyway, and on lavapipe the second stack array and the skipping loop
    // cost more than that step (measured: 30-45% more rays/s without).
    if (t.stackSize == 0u) {
        return false;
    }
    t.ref = t.top0;
    t.top0 = t.top1;
    t.top1 = t.top2;
    t.top2 = t.top3;
    t.top3 = t.top4;
    t.top4 = t.top5;
    t.top5 = t.top6;
    t.top6 = t.top7;
    --t.stackSize;
    if (t.stackSize >= 8u) {
        t.top7 = bvhStackSpill(t.stackSize - 8u);
    }
    return true;
}

// The whole traversal of one ray. Each step visits one interior node or one triangle and none
// twice, so the loop runs fewer than textureSize(bvhTexels) times.
bool bvhTraverse(vec3 origin, vec3 dir, float tMax, bool anyHit, out Hit hit) {
    BvhTraversal t;
    if (bvhBegin(origin, dir, tMax, anyHit, t)) {
        uint texelCount = uint(textureSize(bvhTexels));
        for (uint step = 0u; step < texelCount; ++step) {
            if (!bvhStep(t)) {
                break;
            }
        }
    }
    hit = t.hit;
    return t.found;
}

// Closest hit with 0 < t < tMax. On a miss returns false with hit = {tMax, BVH_NO_HIT, 0, 0}.
bool traceClosest(vec3 origin, vec3 dir, float tMax, out Hit hit) {
    return bvhTraverse(origin, dir, tMax, false, hit);
}

// Whether any triangle is hit with 0 < t < tMax (shadow rays).
bool traceAny(vec3 origin, vec3 dir, float tMax) {
    Hit hit;
    return bvhTraverse(origin, dir, tMax, true, hit);
}

#endif  // PMCR_COMMON_BVH_GLSL
