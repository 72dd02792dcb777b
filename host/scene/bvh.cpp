#include "scene/bvh.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <optional>

#include "core/error.h"
#include "scene/scene.h"

namespace pmcr {

namespace {

// SAH constants (Wald 2007): bins per axis and the cost of one traversal step relative to one
// triangle intersection.
constexpr uint32_t kBinCount = 16;
constexpr float kTraversalCost = 1.0f;

// Triangles with twice their area below this times their longest edge squared (a smallest
// angle of about 1e-5 radians) are never hit (see makeIsectTriangle). The rounding error of
// Moller-Trumbore's float det is a few ulps of |e1| |e2| |d| (about 2.4e-7 of it), so for
// the triangles kept det is right to a few percent even at normal incidence.
constexpr double kSliverSine = 1e-5;

struct Aabb {
    glm::vec3 lo{std::numeric_limits<float>::infinity()};
    glm::vec3 hi{-std::numeric_limits<float>::infinity()};

    void grow(const glm::vec3& p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void grow(const Aabb& b) {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
    // Surface area; 0 for an empty box.
    float area() const {
        const glm::vec3 d = glm::max(hi - lo, glm::vec3(0.0f));
        return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
    }
    // Written as a sum of halves so that it cannot overflow for finite bounds.
    glm::vec3 center() const { return 0.5f * lo + 0.5f * hi; }
};

// Stored node bounds are padded outwards by max(2^-22 |x|, BVH_MIN_BOUNDS_PAD), so that no
// triangle touches a box face. A ray whose origin lies on a face of the unpadded box with a
// zero (or tiny) direction component along that axis then starts strictly inside the slab,
// at least BVH_MIN_BOUNDS_PAD / BVH_MIN_DIRECTION = 1e15 from leaving it, instead of being
// culled at t = 0. The padding is monotone, so children stay inside their parents.
float padAmount(float x) {
    return std::max(std::abs(x) * 0x1p-22f, gpu::BVH_MIN_BOUNDS_PAD);
}
glm::vec3 padDown(const glm::vec3& p) {
    return {p.x - padAmount(p.x), p.y - padAmount(p.y), p.z - padAmount(p.z)};
}
glm::vec3 padUp(const glm::vec3& p) {
    return {p.x + padAmount(p.x), p.y + padAmount(p.y), p.z + padAmount(p.z)};
}

// A triangle as the builder sees it: its bounds and its original index.
struct PrimRef {
    Aabb bounds;
    uint32_t index;
};

// Maps centroids to SAH bins along one axis. The same object classifies during binning and
// during partitioning, so the partition reproduces the binned counts exactly.
struct BinMapping {
    float lo;
    float scale;
    uint32_t operator()(float c) const {
        const auto bin = static_cast<uint32_t>((c - lo) * scale);
        return std::min(bin, kBinCount - 1);
    }
};

struct Split {
    int axis = -1;  // -1: no valid SAH split
    uint32_t bin = 0;
    float cost = std::numeric_limits<float>::infinity();  // in units of one intersection
    BinMapping mapping{};
};

class Builder {
public:
    Builder(std::vector<PrimRef>& refs, std::vector<gpu::BvhNode>& nodes, uint32_t maxDepth)
        : m_refs(refs), m_nodes(nodes), m_maxDepth(maxDepth) {}

    uint32_t depth() const { return m_depth; }

    // Builds the subtree over refs [begin, end) into node `nodeIndex`, whose children are
    // appended to m_nodes as adjacent pairs (depth-first).
    void build(uint32_t nodeIndex, uint32_t begin, uint32_t end, uint32_t depth) {
        Aabb bounds;
        Aabb centroids;
        for (uint32_t i = begin; i < end; ++i) {
            bounds.grow(m_refs[i].bounds);
            centroids.grow(m_refs[i].bounds.center());
        }
        m_nodes[nodeIndex].boundsMin = padDown(bounds.lo);
        m_nodes[nodeIndex].boundsMax = padUp(bounds.hi);

        const uint32_t count = end - begin;
        if (count == 1 || depth == m_maxDepth) {
            makeLeaf(nodeIndex, begin, count, depth);
            return;
        }
        std::optional<uint32_t> mid;
        if (sahAllowed(count, depth)) {
            const Split split = findSplit(begin, end, centroids);
            const float nodeArea = bounds.area();
            const float splitCost = kTraversalCost + split.cost / nodeArea;
            const bool sahValid = split.axis >= 0 && nodeArea > 0.0f && std::isfinite(splitCost);
            // SAH leaf creation: stop when intersecting all triangles is no dearer than a split.
            if (count <= gpu::BVH_MAX_LEAF_TRIANGLES &&
                (!sahValid || static_cast<float>(count) <= splitCost)) {
                makeLeaf(nodeIndex, begin, count, depth);
                return;
            }
            if (sahValid) {
                const auto first = m_refs.begin() + begin;
                const auto middle =
                    std::partition(first, m_refs.begin() + end, [&](const PrimRef& r) {
                        return split.mapping(r.bounds.center()[split.axis]) < split.bin;
                    });
                mid = begin + static_cast<uint32_t>(middle - first);
            }
        }
        if (!mid) {
            mid = medianSplit(begin, end, centroids);
        }
        assert(*mid > begin && *mid < end);

        const auto left = static_cast<uint32_t>(m_nodes.size());
        m_nodes.resize(m_nodes.size() + 2);
        m_nodes[nodeIndex].leftOrFirst = left;
        m_nodes[nodeIndex].count = 0;
        build(left, begin, *mid, depth + 1);
        build(left + 1, *mid, end, depth + 1);
    }

private:
    void makeLeaf(uint32_t nodeIndex, uint32_t begin, uint32_t count, uint32_t depth) {
        assert(count <= gpu::BVH_MAX_LEAF_TRIANGLES && depth <= m_maxDepth);
        m_nodes[nodeIndex].leftOrFirst = begin;
        m_nodes[nodeIndex].count = count;
        m_depth = std::max(m_depth, depth);
    }

    // Depth cap: median splits from depth d reach leaves of BVH_MAX_LEAF_TRIANGLES by depth
    // maxDepth when count <= maxLeaf * 2^(maxDepth - d). SAH may cut off a single triangle,
    // so it is used only while count - 1 still fits below the next level; past that, median
    // splits keep every leaf within both limits. Called only for depth < maxDepth.
    bool sahAllowed(uint32_t count, uint32_t depth) const {
        const uint32_t levelsBelowChild = m_maxDepth - depth - 1;
        if (levelsBelowChild >= 32) {
            return true;
        }
        const uint64_t capacity = uint64_t{gpu::BVH_MAX_LEAF_TRIANGLES} << levelsBelowChild;
        return count - 1 <= capacity;
    }

    // Binned SAH over the three axes (Wald 2007, section 3): cost of the best plane between
    // bins as sum over both sides of (area * triangle count), not yet divided by the node area.
    Split findSplit(uint32_t begin, uint32_t end, const Aabb& centroids) const {
        struct Bin {
            Aabb bounds;
            uint32_t count = 0;
        };
        std::array<std::array<Bin, kBinCount>, 3> bins{};
        std::array<BinMapping, 3> mappings{};
        std::array<bool, 3> usable{};
        for (int axis = 0; axis < 3; ++axis) {
            const float extent = centroids.hi[axis] - centroids.lo[axis];
            usable[axis] = extent > 0.0f && std::isfinite(extent);
            mappings[axis] = {centroids.lo[axis], usable[axis] ? kBinCount / extent : 0.0f};
        }
        for (uint32_t i = begin; i < end; ++i) {
            const glm::vec3 c = m_refs[i].bounds.center();
            for (int axis = 0; axis < 3; ++axis) {
                Bin& bin = bins[axis][mappings[axis](c[axis])];
                bin.bounds.grow(m_refs[i].bounds);
                ++bin.count;
            }
        }

        Split best;
        for (int axis = 0; axis < 3; ++axis) {
            if (!usable[axis]) {
                continue;
            }
            // Sweep from the right: area and count of bins [b, kBinCount) for each plane b.
            std::array<float, kBinCount> rightArea{};
            std::array<uint32_t, kBinCount> rightCount{};
            Aabb acc;
            uint32_t n = 0;
            for (uint32_t b = kBinCount - 1; b > 0; --b) {
                acc.grow(bins[axis][b].bounds);
                n += bins[axis][b].count;
                rightArea[b] = acc.area();
                rightCount[b] = n;
            }
            acc = Aabb{};
            n = 0;
            for (uint32_t b = 1; b < kBinCount; ++b) {
                acc.grow(bins[axis][b - 1].bounds);
                n += bins[axis][b - 1].count;
                if (n == 0 || rightCount[b] == 0) {
                    continue;
                }
                const float cost = acc.area() * static_cast<float>(n) +
                                   rightArea[b] * static_cast<float>(rightCount[b]);
                if (cost < best.cost) {
                    best = {axis, b, cost, mappings[axis]};
                }
            }
        }
        return best;
    }

    // Object median along the widest centroid axis; splits any range of >= 2 refs, even when
    // all centroids coincide.
    uint32_t medianSplit(uint32_t begin, uint32_t end, const Aabb& centroids) {
        const glm::vec3 extent = centroids.hi - centroids.lo;
        int axis = 0;
        if (extent.y > extent[axis]) {
            axis = 1;
        }
        if (extent.z > extent[axis]) {
            axis = 2;
        }
        const uint32_t mid = begin + (end - begin) / 2;
        std::nth_element(m_refs.begin() + begin, m_refs.begin() + mid, m_refs.begin() + end,
                         [axis](const PrimRef& a, const PrimRef& b) {
                             return a.bounds.center()[axis] < b.bounds.center()[axis];
                         });
        return mid;
    }

    std::vector<PrimRef>& m_refs;
    std::vector<gpu::BvhNode>& m_nodes;
    uint32_t m_maxDepth;
    uint32_t m_depth = 0;
};

// Reciprocal direction for the slab test with tiny components clamped to +-BVH_MIN_DIRECTION
// (sign of -0 taken as +), so every slab distance is finite.
glm::vec3 safeInverse(const glm::vec3& dir) {
    glm::vec3 inv;
    for (int i = 0; i < 3; ++i) {
        const float d = std::abs(dir[i]) < gpu::BVH_MIN_DIRECTION
                            ? (dir[i] < 0.0f ? -gpu::BVH_MIN_DIRECTION : gpu::BVH_MIN_DIRECTION)
                            : dir[i];
        inv[i] = 1.0f / d;
    }
    return inv;
}

// Slab test (Kay & Kajiya 1986) against [0, tMax]; tNear is the entry distance, clamped to 0.
inline bool intersectBox(const gpu::BvhNode& node, const glm::vec3& origin, const glm::vec3& invDir,
                         float tMax, float& tNear) {
    const glm::vec3 t0 = (node.boundsMin - origin) * invDir;
    const glm::vec3 t1 = (node.boundsMax - origin) * invDir;
    const glm::vec3 tMin = glm::min(t0, t1);
    const glm::vec3 tMaxV = glm::max(t0, t1);
    tNear = std::max(std::max(tMin.x, tMin.y), std::max(tMin.z, 0.0f));
    const float tFar =
        std::min(std::min(std::min(tMaxV.x, tMaxV.y), tMaxV.z) * gpu::BVH_BOX_EXIT_SCALE, tMax);
    return tNear <= tFar;
}

}  // namespace

gpu::IsectTriangle makeIsectTriangle(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2,
                                     uint32_t index) {
    gpu::IsectTriangle tri;
    tri.v0 = glm::vec4(p0, std::bit_cast<float>(index));
    tri.e1 = glm::vec4(p1 - p0, 0.0f);
    tri.e2 = glm::vec4(p2 - p0, 0.0f);
    // Slivers: twice the area against the longest edge squared, in double so that the test
    // itself is exact enough. Their float det, u, v and t are rounding noise, so a ray passing
    // near their line would report a hit anywhere along it; zero edges make det exactly 0.
    const glm::dvec3 e1(tri.e1);
    const glm::dvec3 e2(tri.e2);
    const double twiceArea = glm::length(glm::cross(e1, e2));
    const double longest2 =
        std::max({glm::dot(e1, e1), glm::dot(e2, e2), glm::dot(e2 - e1, e2 - e1)});
    if (!(twiceArea > kSliverSine * longest2)) {
        tri.e1 = glm::vec4(0.0f);
        tri.e2 = glm::vec4(0.0f);
    }
    return tri;
}

Bvh Bvh::build(std::span<const gpu::Vertex> vertices, std::span<const gpu::Triangle> triangles,
               const std::string& source, uint32_t maxDepth) {
    if (triangles.empty()) {
        fail(source, "no triangles to build a BVH over");
    }
    if (triangles.size() > (std::numeric_limits<uint32_t>::max() >> 1)) {
        fail(source, "too many triangles for a BVH (" + std::to_string(triangles.size()) + ")");
    }
    for (size_t i = 0; i < vertices.size(); ++i) {
        const glm::vec3& p = vertices[i].position;
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            fail(source, "vertex " + std::to_string(i) + " has a non-finite position");
        }
    }

    const auto count = static_cast<uint32_t>(triangles.size());
    std::vector<PrimRef> refs(count);
    for (uint32_t i = 0; i < count; ++i) {
        const gpu::Triangle& t = triangles[i];
        for (const uint32_t v : {t.i0, t.i1, t.i2}) {
            if (v >= vertices.size()) {
                fail(source, "triangle " + std::to_string(i) + " uses vertex " + std::to_string(v) +
                                 " of " + std::to_string(vertices.size()));
            }
        }
        refs[i].bounds.grow(vertices[t.i0].position);
        refs[i].bounds.grow(vertices[t.i1].position);
        refs[i].bounds.grow(vertices[t.i2].position);
        refs[i].index = i;
    }

    Bvh bvh;
    bvh.m_nodes.reserve(2 * size_t{count} - 1);
    bvh.m_nodes.resize(1);
    // The shallowest cap that median splits can meet is ceil(log2(count / maxLeaf)).
    uint32_t minDepth = 0;
    while ((uint64_t{gpu::BVH_MAX_LEAF_TRIANGLES} << minDepth) < count) {
        ++minDepth;
    }
    Builder builder(refs, bvh.m_nodes, std::clamp(maxDepth, minDepth, gpu::BVH_MAX_DEPTH));
    builder.build(0, 0, count, 0);
    bvh.m_depth = builder.depth();

    // Leaves index refs; store their triangles in that order.
    bvh.m_triangles.resize(count);
    for (uint32_t i = 0; i < count; ++i) {
        const gpu::Triangle& t = triangles[refs[i].index];
        bvh.m_triangles[i] = makeIsectTriangle(vertices[t.i0].position, vertices[t.i1].position,
                                               vertices[t.i2].position, refs[i].index);
    }
    return bvh;
}

std::vector<glm::uvec4> Bvh::deviceTexels() const {
    // Each 4-wide node is a binary interior node with its two children opened: its children
    // are the binary node's grandchildren, or a binary child itself where that is a leaf (a
    // binary root that is a leaf becomes the one child of the wide root). So a binary leaf at
    // depth d sits below ceil(d / 2) wide nodes, and the traversal's stack bound holds
    // (BVH_STACK_SIZE in shared/scene_types.h). Wide nodes are numbered breadth first.
    std::vector<std::array<uint32_t, gpu::BVH_WIDTH>> children;  // binary nodes, per wide node
    std::vector<uint32_t> childCount;
    std::vector<uint32_t> wideIndex(m_nodes.size(), 0);  // of a binary node that roots one
    std::vector<uint32_t> queue{0};
    for (size_t q = 0; q < queue.size(); ++q) {
        const gpu::BvhNode& root = m_nodes[queue[q]];
        std::vector<uint32_t> kids;
        if (root.count > 0) {
            kids.push_back(queue[q]);
        } else {
            for (const uint32_t c : {root.leftOrFirst, root.leftOrFirst + 1}) {
                if (m_nodes[c].count > 0) {
                    kids.push_back(c);
                } else {
                    kids.push_back(m_nodes[c].leftOrFirst);
                    kids.push_back(m_nodes[c].leftOrFirst + 1);
                }
            }
        }
        std::array<uint32_t, gpu::BVH_WIDTH> slots{};
        for (size_t k = 0; k < kids.size(); ++k) {
            slots[k] = kids[k];
            if (m_nodes[kids[k]].count == 0) {
                wideIndex[kids[k]] = uint32_t(queue.size());
                queue.push_back(kids[k]);
            }
        }
        children.push_back(slots);
        childCount.push_back(uint32_t(kids.size()));
    }

    const size_t triangleBase = size_t{gpu::BVH_NODE_TEXELS} * children.size();
    const size_t texelCount = triangleBase + size_t{gpu::BVH_TRIANGLE_TEXELS} * m_triangles.size();
    if (texelCount > gpu::BVH_MAX_TEXELS) {
        throw Error("BVH of " + std::to_string(m_triangles.size()) + " triangles needs " +
                    std::to_string(texelCount) + " texels, more than the kernels address (" +
                    std::to_string(gpu::BVH_MAX_TEXELS) + ")");
    }
    std::vector<glm::uvec4> texels(texelCount);
    for (size_t w = 0; w < children.size(); ++w) {
        glm::uvec4* node = &texels[gpu::BVH_NODE_TEXELS * w];
        for (uint32_t k = 0; k < gpu::BVH_WIDTH; ++k) {
            uint32_t ref = gpu::BVH_EMPTY_CHILD;
            glm::vec3 lo(0.0f);
            glm::vec3 hi(0.0f);
            if (k < childCount[w]) {
                const gpu::BvhNode& n = m_nodes[children[w][k]];
                lo = n.boundsMin;
                hi = n.boundsMax;
                const size_t address =
                    n.count > 0 ? triangleBase + size_t{gpu::BVH_TRIANGLE_TEXELS} * n.leftOrFirst
                                : size_t{gpu::BVH_NODE_TEXELS} * wideIndex[children[w][k]];
                ref = (uint32_t(address) << 3) | n.count;
            }
            for (int axis = 0; axis < 3; ++axis) {
                node[axis][k] = std::bit_cast<uint32_t>(lo[axis]);
                node[3 + axis][k] = std::bit_cast<uint32_t>(hi[axis]);
            }
            node[gpu::BVH_NODE_REFS_TEXEL][k] = ref;
        }
    }
    for (size_t i = 0; i < m_triangles.size(); ++i) {
        const gpu::IsectTriangle& t = m_triangles[i];
        glm::uvec4* triangle = &texels[triangleBase + gpu::BVH_TRIANGLE_TEXELS * i];
        triangle[0] = std::bit_cast<glm::uvec4>(t.v0);
        triangle[1] = std::bit_cast<glm::uvec4>(t.e1);
        triangle[2] = std::bit_cast<glm::uvec4>(t.e2);
    }
    return texels;
}

Bvh Bvh::build(const Scene& scene) {
    Bvh bvh = build(scene.vertices, scene.triangles, scene.path.string());
    // Alpha-masked triangles carry their mask in the unused w components (shared/scene_types.h
    // IsectTriangle), so the traversal tests it without reading the material.
    for (gpu::IsectTriangle& t : bvh.m_triangles) {
        const uint32_t index = std::bit_cast<uint32_t>(t.v0.w);
        const gpu::Material& m = scene.materials[scene.triangles[index].material];
        if (m.alphaCutoff > 0.0f && m.baseColorTexture >= 0) {
            t.e1.w = std::bit_cast<float>(uint32_t(m.baseColorTexture) + 1u);
            t.e2.w = m.alphaCutoff;
        }
    }
    return bvh;
}

// Ordered traversal (near child first) of adjacent child pairs: each step tests both child
// boxes of an interior node, descends into the nearer and pushes the farther with its entry
// distance, which is re-checked against the closest hit when popped.
template <bool kAnyHit>
bool Bvh::traverse(const glm::vec3& origin, const glm::vec3& dir, gpu::Hit& hit) const {
    const glm::vec3 invDir = safeInverse(dir);
    float tEntry;
    if (!intersectBox(m_nodes[0], origin, invDir, hit.t, tEntry)) {
        return false;
    }
    struct Entry {
        uint32_t node;
        float tEntry;
    };
    std::array<Entry, gpu::BVH_MAX_DEPTH> stack;
    uint32_t stackSize = 0;
    uint32_t node = 0;
    bool found = false;
    for (;;) {
        const gpu::BvhNode& n = m_nodes[node];
        if (n.count > 0) {
            for (uint32_t i = n.leftOrFirst; i < n.leftOrFirst + n.count; ++i) {
                if (intersectTriangle(m_triangles[i], origin, dir, hit)) {
                    if constexpr (kAnyHit) {
                        return true;
                    }
                    found = true;
                }
            }
        } else {
            const uint32_t left = n.leftOrFirst;
            float tLeft;
            float tRight;
            const bool hitLeft = intersectBox(m_nodes[left], origin, invDir, hit.t, tLeft);
            const bool hitRight = intersectBox(m_nodes[left + 1], origin, invDir, hit.t, tRight);
            if (hitLeft && hitRight) {
                const bool leftFirst = tLeft <= tRight;
                if (stackSize < gpu::BVH_MAX_DEPTH) {
                    stack[stackSize++] = leftFirst ? Entry{left + 1, tRight} : Entry{left, tLeft};
                }
                node = leftFirst ? left : left + 1;
                continue;
            }
            if (hitLeft || hitRight) {
                node = hitLeft ? left : left + 1;
                continue;
            }
        }
        // Pop the next subtree that can still hold a closer hit.
        do {
            if (stackSize == 0) {
                return found;
            }
            --stackSize;
        } while (stack[stackSize].tEntry > hit.t);
        node = stack[stackSize].node;
    }
}

bool Bvh::traceClosest(const glm::vec3& origin, const glm::vec3& dir, float tMax,
                       gpu::Hit& hit) const {
    hit = {tMax, gpu::BVH_NO_HIT, 0.0f, 0.0f};
    return traverse<false>(origin, dir, hit);
}

bool Bvh::traceAny(const glm::vec3& origin, const glm::vec3& dir, float tMax) const {
    gpu::Hit hit{tMax, gpu::BVH_NO_HIT, 0.0f, 0.0f};
    return traverse<true>(origin, dir, hit);
}

}  // namespace pmcr
