// Bounding volume hierarchy over the scene's world-space triangles: a binned SAH build
// (Wald 2007, "On fast Construction of SAH-based Bounding Volume Hierarchies"), flattened into
// binary nodes and triangles (gpu::BvhNode, gpu::IsectTriangle in shared/scene_types.h); the
// kernels read the same tree collapsed to 4-wide nodes, serialized into one texel buffer
// (deviceTexels), and the scalar CPU traversal of the binary nodes is the reference for
// shaders/common/bvh.glsl (the same closest hits).
//
// Intersection policy (identical in C++ and GLSL):
//  - Moller-Trumbore (1997) with a division-free inside test: the barycentric numerators are
//    compared against |det| before anything is divided, edges and vertices count as inside,
//    and only det == 0 (a ray parallel to the triangle, or a degenerate triangle) is rejected.
//    No epsilon: shared edges are hit by at least one side up to float rounding of u, v (this
//    is not the watertight test of Woop et al. 2013; cracks are a few ulps wide).
//  - A hit counts when 0 < t < tMax, strictly. Avoiding self-intersection is the caller's
//    job (offset the origin along the geometric normal); the traversal adds no epsilon.
//  - Ray/box slabs use a safe reciprocal direction (BVH_MIN_DIRECTION) and scale the exit
//    distance by BVH_BOX_EXIT_SCALE, so boxes are never culled by rounding. A ray lying
//    exactly in a box face plane with a zero direction component may miss the box; it can
//    only graze triangles there.
#pragma once

#include <bit>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "shared/host_device.h"

namespace pmcr {

struct Scene;

// Intersection-ready form of triangle (p0, p1, p2) with original index `index`.
gpu::IsectTriangle makeIsectTriangle(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2,
                                     uint32_t index);

// Intersects origin + t * dir with `tri`; on a hit with 0 < t < hit.t, overwrites `hit`.
// The BVH traversal and every brute-force reference call this one function.
inline bool intersectTriangle(const gpu::IsectTriangle& tri, const glm::vec3& origin,
                              const glm::vec3& dir, gpu::Hit& hit) {
    const glm::vec3 e1(tri.e1);
    const glm::vec3 e2(tri.e2);
    // Moller & Trumbore 1997: det = e1 . (d x e2), u = s . (d x e2), v = d . (s x e1),
    // t = e2 . (s x e1), all scaled by 1 / det; here folded to |det| before any division.
    const glm::vec3 p = glm::cross(dir, e2);
    const float det = glm::dot(e1, p);
    const float sign = det < 0.0f ? -1.0f : 1.0f;
    const float absDet = det * sign;
    const glm::vec3 s = origin - glm::vec3(tri.v0);
    const float u = glm::dot(s, p) * sign;
    if (!(absDet > 0.0f) || u < 0.0f || u > absDet) {
        return false;
    }
    const glm::vec3 q = glm::cross(s, e1);
    const float v = glm::dot(dir, q) * sign;
    if (v < 0.0f || u + v > absDet) {
        return false;
    }
    const float invDet = 1.0f / absDet;
    const float t = glm::dot(e2, q) * sign * invDet;
    if (!(t > 0.0f) || !(t < hit.t)) {
        return false;
    }
    hit.t = t;
    hit.triangle = std::bit_cast<uint32_t>(tri.v0.w);
    hit.b1 = u * invDet;
    hit.b2 = v * invDet;
    return true;
}

class Bvh {
public:
    // Builds over `triangles` (indices into `vertices`). `source` names the input in errors:
    // throws pmcr::Error for no triangles, a vertex index out of range or a non-finite position.
    // maxDepth caps the leaf depth; it is clamped to BVH_MAX_DEPTH (the kernels' stack size)
    // and raised to the least depth that leaves of BVH_MAX_LEAF_TRIANGLES can meet.
    static Bvh build(std::span<const gpu::Vertex> vertices,
                     std::span<const gpu::Triangle> triangles, const std::string& source,
                     uint32_t maxDepth = gpu::BVH_MAX_DEPTH);
    // The scene's BVH, with alpha-masked triangles marked (IsectTriangle). The CPU traversal
    // below ignores the marks: it treats every triangle as opaque.
    static Bvh build(const Scene& scene);

    const std::vector<gpu::BvhNode>& nodes() const { return m_nodes; }
    const std::vector<gpu::IsectTriangle>& triangles() const { return m_triangles; }
    uint32_t depth() const { return m_depth; }  // deepest leaf; the root has depth 0

    // The tree as the kernels read it: one array of 16-byte texels, the binary tree collapsed
    // to 4-wide nodes (each interior node with its two children opened), then the triangles,
    // three texels each (layout in shared/scene_types.h). Throws pmcr::Error when the
    // addresses do not fit (BVH_MAX_TEXELS).
    std::vector<glm::uvec4> deviceTexels() const;

    // Closest hit with 0 < t < tMax. On a miss returns false and sets hit to
    // {tMax, BVH_NO_HIT, 0, 0}. Mirrors traceClosest() in shaders/common/bvh.glsl.
    bool traceClosest(const glm::vec3& origin, const glm::vec3& dir, float tMax,
                      gpu::Hit& hit) const;
    // Whether any triangle is hit with 0 < t < tMax (shadow rays). Mirrors traceAny().
    bool traceAny(const glm::vec3& origin, const glm::vec3& dir, float tMax) const;

private:
    template <bool kAnyHit>
    bool traverse(const glm::vec3& origin, const glm::vec3& dir, gpu::Hit& hit) const;

    std::vector<gpu::BvhNode> m_nodes;
    std::vector<gpu::IsectTriangle> m_triangles;
    uint32_t m_depth = 0;
};

}  // namespace pmcr
