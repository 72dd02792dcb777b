// BVH traversal used by every kernel: closest hit and any hit on the 4-wide form of the BVH
// that host/scene/bvh.cpp builds. The arithmetic (intersection tests, epsilon policy) is that
// of Bvh::traceClosest / Bvh::traceAny, which traverse the binary tree and give the same
// closest hits (up to which of two triangles sharing an edge reports it); see
// host/scene/bvh.h for the policy: Moller-Trumbore with a division-free inside test and
// inclusive edges, hits with 0 < t < tMax, no self-intersection epsilon (offset origins in the
// caller).
//
// The BVH is one uniform texel buffer of uvec4 (Bvh::deviceTexels, layout in
// shared/scene_types.h): a wide node is BVH_NODE_TEXELS texels, its four children's boxes as
// structure of arrays and their refs; a triangle is three texels (v0 + original index, e1, e2).
//
// Written for SIMD-on-CPU implementations (lavapipe runs 8 invocations as the lanes of one
// vector, both sides of a divergent branch under masks), where memory reads dominate: a texel
// fetch is a vector gather, while an SSBO load with per-lane addresses is a loop over the
// lanes. So each traversal step is one "if-if" step (Aila & Laine 2009, "Understanding the
// Efficiency of Ray Traversal on GPUs") that does the same seven texel fetches in every lane,
// whatever the lane is doing: a wide node (7 texels), or two triangles of a leaf (6 texels).
// Four children a step take about half the steps of the binary tree's two (bench/throughput
// --steps), 1.1-1.3x the rays per second on lavapipe (docs/benchmarks.md, issue 20).
//
// Bounds: the stack holds BVH_STACK_SIZE node references (near child first pushes at most
// three children per wide node, and leaves lie below at most BVH_MAX_DEPTH / 2 wide nodes);
// each step visits one wide node or two triangles and none twice, so the loop runs fewer than
// textureSize(bvhTexels) times.
#ifndef PMCR_COMMON_BVH_GLSL
#define PMCR_COMMON_BVH_GLSL

#include "common/math.glsl"

layout(set = SCENE_SET, binding = BINDING_BVH) uniform usamplerBuffer bvhTexels;

uvec4 bvhTexel(uint i) { return texelFetch(bvhTexels, int(i)); }

#ifdef BVH_COUNT_STEPS
// Diagnostics only (shaders/bench/trace_rays_steps.comp): the steps of the last traversal.
uint bvhNodeSteps = 0u;
uint bvhLeafSteps = 0u;
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

// The stack below the traversal's eight register entries: BVH_STACK_SIZE - 8 entries per
// invocation in workgroup-shared memory (16 KiB for 64 invocations, Vulkan's minimum of
// maxComputeSharedMemorySize); every kernel that traces has local_size_x = WORKGROUP_SIZE. An
// invocation runs one traversal at a time. On lavapipe pt's kernel samples 1.4-1.6x faster
// with a shared array than with a private one doing the same accesses (three paired runs of
// bench/throughput, issue 20; images the same bit for bit), while the bench's traversal-only
// kernel runs as fast with either.
const uint BVH_REGISTER_ENTRIES = 8u;  // top0..top7 of BvhTraversal
const uint BVH_SPILL_ENTRIES = BVH_STACK_SIZE - BVH_REGISTER_ENTRIES;
shared uint bvhStackSpillShared[WORKGROUP_SIZE * BVH_SPILL_ENTRIES];
#define bvhStackSpill(i) bvhStackSpillShared[gl_LocalInvocationIndex * BVH_SPILL_ENTRIES + (i)]

// A traversal in progress: near-child-first, with anyHit it ends at the first hit. bvhBegin
// starts one, each bvhStep takes one step (a wide step tests four child boxes, descends into
// the nearest hit and pushes the others; a leaf step tests two triangles), so that a kernel
// can run the steps of several rays in turn in one loop (trace_rays.glsl) as well as one ray's.
struct BvhTraversal {
    vec3 origin;
    vec3 dir;
    vec3 invDir;
    Hit hit;          // the closest hit so far; its t bounds the search
    uint ref;         // the next step's node or triangles (a ref, shared/scene_types.h)
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

// Starts the traversal of origin + t dir for hits with 0 < t < tMax at the root node (the
// root's own box is not stored: the first step tests its children's).
void bvhBegin(vec3 origin, vec3 dir, float tMax, bool anyHit, out BvhTraversal t) {
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
    t.ref = 0u;  // wide node 0
}

// k == 0 ? a0 : k == 1 ? a1 : k == 2 ? a2 : a3.
uint bvhPick(uint k, uint a0, uint a1, uint a2, uint a3) {
    return k == 0u ? a0 : (k == 1u ? a1 : (k == 2u ? a2 : a3));
}

// Pushes the last k of far, middle, near (k <= 3), in that order, so that near ends on top.
// The entries that leave the eight registers are stored from one site in a loop, not one per
// pushed child: on lavapipe each shared-memory access site is a loop over the lanes that runs
// every step, whether or not a lane stores (docs/benchmarks.md, writing kernels for lavapipe).
void bvhPush(inout BvhTraversal t, uint k, uint far, uint middle, uint near) {
    uint s = t.stackSize;
    if (s + k > BVH_STACK_SIZE) {
        return;  // never: the stack bound (top of this file) keeps s + k <= BVH_STACK_SIZE
    }
    // Registers top_i with i in [8 - k, 7] and i < s leave for memory, deepest first; the
    // entry at depth d (0 = the bottom of the stack) is stored at bvhStackSpill(d).
    uint inRegisters = min(s, BVH_REGISTER_ENTRIES);
    uint leaving = inRegisters + k > BVH_REGISTER_ENTRIES ? inRegisters + k - BVH_REGISTER_ENTRIES
                                                          : 0u;
    uint deepest = inRegisters - 1u;  // top_i of the first to leave
    uint depth = s - inRegisters;     // its depth
    for (uint j = 0u; j < leaving; ++j) {
        uint i = deepest - j;
        bvhStackSpill(depth + j) = i == 7u ? t.top7 : (i == 6u ? t.top6 : t.top5);
    }
    t.top7 = bvhPick(k, t.top7, t.top6, t.top5, t.top4);
    t.top6 = bvhPick(k, t.top6, t.top5, t.top4, t.top3);
    t.top5 = bvhPick(k, t.top5, t.top4, t.top3, t.top2);
    t.top4 = bvhPick(k, t.top4, t.top3, t.top2, t.top1);
    t.top3 = bvhPick(k, t.top3, t.top2, t.top1, t.top0);
    t.top2 = bvhPick(k, t.top2, t.top1, t.top0, far);
    t.top1 = bvhPick(k, t.top1, t.top0, middle, middle);
    t.top0 = bvhPick(k, t.top0, near, near, near);
    t.stackSize = s + k;
}

// One compare-exchange of a sorting network on (entry distance, ref) pairs.
void bvhSortPair(inout float ta, inout uint ra, inout float tb, inout uint rb) {
    bool swap = tb < ta;
    float t = ta;
    uint r = ra;
    ta = swap ? tb : ta;
    ra = swap ? rb : ra;
    tb = swap ? t : tb;
    rb = swap ? r : rb;
}

// One step of traversal t. Returns false when the traversal has ended (t.found and t.hit are
// then final).
bool bvhStep(inout BvhTraversal t) {
    uint count = t.ref & 7u;
    uint address = t.ref >> 3;
    bool leaf = count > 0u;
#ifdef BVH_COUNT_STEPS
    if (leaf) {
        ++bvhLeafSteps;
    } else {
        ++bvhNodeSteps;
    }
#endif
    // The same seven fetches in every lane: a wide node, or a leaf's next two triangles (with
    // one triangle left, the second three fetches repeat it, so none reads past the last).
    bool one = leaf && count < 2u;
    uvec4 w0 = bvhTexel(address);
    uvec4 w1 = bvhTexel(address + 1u);
    uvec4 w2 = bvhTexel(address + 2u);
    uvec4 w3 = bvhTexel(one ? address : address + 3u);
    uvec4 w4 = bvhTexel(one ? address + 1u : address + 4u);
    uvec4 w5 = bvhTexel(one ? address + 2u : address + 5u);
    uvec4 w6 = bvhTexel(leaf ? address : address + BVH_NODE_REFS_TEXEL);  // the refs
    bool next = false;  // t.ref is set to the next node or triangles
    if (leaf) {
        if (bvhIntersectTriangle(uintBitsToFloat(w0), uintBitsToFloat(w1), uintBitsToFloat(w2),
                                 t.origin, t.dir, t.hit)) {
            t.found = true;
        }
        if (!one && bvhIntersectTriangle(uintBitsToFloat(w3), uintBitsToFloat(w4),
                                         uintBitsToFloat(w5), t.origin, t.dir, t.hit)) {
            t.found = true;
        }
        if (count > 2u) {
            t.ref = ((address + 2u * BVH_TRIANGLE_TEXELS) << 3) | (count - 2u);
            next = true;
        }
    } else {
        // Slab tests (Kay & Kajiya 1986) of the four boxes against [0, hit.t], the exit
        // distances scaled by 1 + 2 gamma(3) (pbrt-v4 Bounds3::IntersectP).
        vec3 o = t.origin;
        vec3 inv = t.invDir;
        vec4 x0 = (uintBitsToFloat(w0) - o.x) * inv.x;
        vec4 y0 = (uintBitsToFloat(w1) - o.y) * inv.y;
        vec4 z0 = (uintBitsToFloat(w2) - o.z) * inv.z;
        vec4 x1 = (uintBitsToFloat(w3) - o.x) * inv.x;
        vec4 y1 = (uintBitsToFloat(w4) - o.y) * inv.y;
        vec4 z1 = (uintBitsToFloat(w5) - o.z) * inv.z;
        vec4 tNear = max(max(min(x0, x1), min(y0, y1)), max(min(z0, z1), vec4(0.0)));
        vec4 tFar = min(min(max(x0, x1), max(y0, y1)), max(z0, z1)) * BVH_BOX_EXIT_SCALE;
        bvec4 hits = bvec4(uvec4(lessThanEqual(tNear, min(tFar, vec4(t.hit.t)))) &
                           uvec4(notEqual(w6, uvec4(BVH_EMPTY_CHILD))));
        // The hit children nearest first (a five-exchange sorting network). Misses sort last:
        // their key is above every hit's, which is at most hit.t <= FLOAT_MAX, clamped below.
        vec4 key = mix(vec4(FLOAT_MAX), min(tNear, vec4(1e38)), hits);
        float t0 = key.x, t1 = key.y, t2 = key.z, t3 = key.w;
        uint r0 = w6.x, r1 = w6.y, r2 = w6.z, r3 = w6.w;
        bvhSortPair(t0, r0, t1, r1);
        bvhSortPair(t2, r2, t3, r3);
        bvhSortPair(t0, r0, t2, r2);
        bvhSortPair(t1, r1, t3, r3);
        bvhSortPair(t1, r1, t2, r2);
        uint hitCount = uint(hits.x) + uint(hits.y) + uint(hits.z) + uint(hits.w);
        // Descend into the nearest; push the others farthest first, so that the nearer pop
        // first.
        bvhPush(t, hitCount > 0u ? hitCount - 1u : 0u, r3, r2, r1);
        if (hitCount >= 1u) {
            t.ref = r0;
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
    if (t.stackSize >= BVH_REGISTER_ENTRIES) {
        t.top7 = bvhStackSpill(t.stackSize - BVH_REGISTER_ENTRIES);
    }
    return true;
}

#ifdef BVH_COUNT_STEPS
// Every traversal step this invocation has taken: for a kernel that keeps its loop iterations
// within lavapipe's budget per invocation (methods/bdpt/bdpt_connect_kernel.glsl).
uint bvhStepsTaken = 0u;
#endif

// The whole traversal of one ray. Each step visits one wide node or two triangles and none
// twice, so the loop runs fewer than textureSize(bvhTexels) times.
bool bvhTraverse(vec3 origin, vec3 dir, float tMax, bool anyHit, out Hit hit) {
    BvhTraversal t;
    bvhBegin(origin, dir, tMax, anyHit, t);
    uint texelCount = uint(textureSize(bvhTexels));
    for (uint step = 0u; step < texelCount; ++step) {
#ifdef BVH_COUNT_STEPS
        bvhStepsTaken += 1u;
#endif
        if (!bvhStep(t)) {
            break;
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
