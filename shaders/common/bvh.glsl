// BVH traversal used by every kernel: closest hit and any hit on the flattened binary BVH that
// host/scene/bvh.cpp builds. The arithmetic (intersection tests, epsilon policy, traversal
// order) is that of Bvh::traceClosest / Bvh::traceAny; see host/scene/bvh.h for the policy:
// Moller-Trumbore with a division-free inside test and inclusive edges, hits with
// 0 < t < tMax, no self-intersection epsilon (offset origins in the caller).
//
// The includer includes shared/host_device.h and declares the scene buffers, scalar layout:
//   layout(set = SCENE_SET, binding = BINDING_BVH_NODES, scalar) readonly buffer BvhNodes {
//       BvhNode bvhNodes[];
//   };
//   layout(set = SCENE_SET, binding = BINDING_ISECT_TRIANGLES, scalar)
//       readonly buffer IsectTriangles { IsectTriangle isectTriangles[]; };
//
// Bounds: the stack holds BVH_MAX_DEPTH node indices (near child first pushes at most one
// sibling per level, and the builder caps leaf depth at BVH_MAX_DEPTH); each loop iteration
// visits one node and no node is visited twice, so the loop runs at most bvhNodes.length()
// times; a leaf holds at most BVH_MAX_LEAF_TRIANGLES triangles.
#ifndef PMCR_COMMON_BVH_GLSL
#define PMCR_COMMON_BVH_GLSL

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
bool bvhIntersectTriangle(uint index, vec3 origin, vec3 dir, inout Hit hit) {
    vec4 v0 = isectTriangles[index].v0;
    vec3 e1 = isectTriangles[index].e1.xyz;
    vec3 e2 = isectTriangles[index].e2.xyz;
    vec3 p = cross(dir, e2);
    float det = dot(e1, p);
    float sgn = det < 0.0 ? -1.0 : 1.0;
    float absDet = det * sgn;
    vec3 s = origin - v0.xyz;
    float u = dot(s, p) * sgn;
    if (!(absDet > 0.0) || u < 0.0 || u > absDet) {
        return false;
    }
    vec3 q = cross(s, e1);
    float v = dot(dir, q) * sgn;
    if (v < 0.0 || u + v > absDet) {
        return false;
    }
    float invDet = 1.0 / absDet;
    float t = dot(e2, q) * sgn * invDet;
    if (!(t > 0.0) || !(t < hit.t)) {
        return false;
    }
    hit = Hit(t, floatBitsToUint(v0.w), u * invDet, v * invDet);
    return true;
}

// Near-child-first traversal of adjacent child pairs; with anyHit it returns at the first hit.
bool bvhTraverse(vec3 origin, vec3 dir, bool anyHit, inout Hit hit) {
    vec3 invDir = bvhSafeInverse(dir);
    float tEntry;
    if (!bvhIntersectBox(bvhNodes[0].boundsMin, bvhNodes[0].boundsMax, origin, invDir, hit.t,
                         tEntry)) {
        return false;
    }
    uint stack[BVH_MAX_DEPTH];
    uint stackSize = 0u;
    uint node = 0u;
    bool found = false;
    uint nodeCount = uint(bvhNodes.length());
    for (uint visit = 0u; visit < nodeCount; ++visit) {
        uint count = bvhNodes[node].count;
        uint first = bvhNodes[node].leftOrFirst;
        if (count > 0u) {
            for (uint i = 0u; i < BVH_MAX_LEAF_TRIANGLES; ++i) {
                if (i >= count) {
                    break;
                }
                if (bvhIntersectTriangle(first + i, origin, dir, hit)) {
                    if (anyHit) {
                        return true;
                    }
                    found = true;
                }
            }
        } else {
            float tLeft;
            float tRight;
            bool hitLeft = bvhIntersectBox(bvhNodes[first].boundsMin, bvhNodes[first].boundsMax,
                                           origin, invDir, hit.t, tLeft);
            bool hitRight =
                bvhIntersectBox(bvhNodes[first + 1u].boundsMin, bvhNodes[first + 1u].boundsMax,
                                origin, invDir, hit.t, tRight);
            if (hitLeft && hitRight) {
                bool leftFirst = tLeft <= tRight;
                if (stackSize < BVH_MAX_DEPTH) {
                    stack[stackSize++] = leftFirst ? first + 1u : first;
                }
                node = leftFirst ? first : first + 1u;
                continue;
            }
            if (hitLeft || hitRight) {
                node = hitLeft ? first : first + 1u;
                continue;
            }
        }
        if (stackSize == 0u) {
            break;
        }
        node = stack[--stackSize];
    }
    return found;
}

// Closest hit with 0 < t < tMax. On a miss returns false with hit = {tMax, BVH_NO_HIT, 0, 0}.
bool traceClosest(vec3 origin, vec3 dir, float tMax, out Hit hit) {
    hit = Hit(tMax, BVH_NO_HIT, 0.0, 0.0);
    return bvhTraverse(origin, dir, false, hit);
}

// Whether any triangle is hit with 0 < t < tMax (shadow rays).
bool traceAny(vec3 origin, vec3 dir, float tMax) {
    Hit hit = Hit(tMax, BVH_NO_HIT, 0.0, 0.0);
    return bvhTraverse(origin, dir, true, hit);
}

#endif  // PMCR_COMMON_BVH_GLSL
