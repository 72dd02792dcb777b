// BVH build and CPU traversal against brute force, structural invariants, degenerate input.
// DISABLED_Throughput is a benchmark to run by hand:
//   pmcr_host_tests --gtest_also_run_disabled_tests --gtest_filter='Bvh.DISABLED_Throughput'
#include <gtest/gtest.h>

#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include "core/error.h"
#include "scene/bvh.h"
#include "scene/scene.h"

namespace pmcr {
namespace {

struct Mesh {
    std::vector<gpu::Vertex> vertices;
    std::vector<gpu::Triangle> triangles;

    void addVertex(const glm::vec3& p) {
        gpu::Vertex v{};
        v.position = p;
        vertices.push_back(v);
    }
    void addTriangle(uint32_t a, uint32_t b, uint32_t c) { triangles.push_back({a, b, c, 0}); }
    void addTriangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
        const auto base = static_cast<uint32_t>(vertices.size());
        addVertex(a);
        addVertex(b);
        addVertex(c);
        addTriangle(base, base + 1, base + 2);
    }
    glm::vec3 position(uint32_t triangle, int corner) const {
        const gpu::Triangle& t = triangles[triangle];
        return vertices[corner == 0 ? t.i0 : corner == 1 ? t.i1 : t.i2].position;
    }
    void bounds(glm::vec3& lo, glm::vec3& hi) const {
        lo = glm::vec3(INFINITY);
        hi = glm::vec3(-INFINITY);
        for (const gpu::Vertex& v : vertices) {
            lo = glm::min(lo, v.position);
            hi = glm::max(hi, v.position);
        }
    }
};

glm::vec3 uniformIn(std::mt19937& rng, const glm::vec3& lo, const glm::vec3& hi) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    return lo + (hi - lo) * glm::vec3(u(rng), u(rng), u(rng));
}

glm::vec3 randomDirection(std::mt19937& rng) {
    std::normal_distribution<float> n;
    for (;;) {
        const glm::vec3 d(n(rng), n(rng), n(rng));
        if (glm::dot(d, d) > 1e-6f) {
            return glm::normalize(d);
        }
    }
}

// Triangles of random size and orientation scattered in a box.
Mesh randomSoup(uint32_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> size(0.01f, 0.5f);
    Mesh mesh;
    for (uint32_t i = 0; i < count; ++i) {
        const glm::vec3 c = uniformIn(rng, glm::vec3(-5.0f), glm::vec3(5.0f));
        const float s = size(rng);
        mesh.addTriangle(c + s * randomDirection(rng), c + s * randomDirection(rng),
                         c + s * randomDirection(rng));
    }
    return mesh;
}

// UV sphere with shared vertices: a closed mesh with shared edges.
Mesh sphere(uint32_t rings, uint32_t segments, float radius, const glm::vec3& center) {
    Mesh mesh;
    for (uint32_t r = 0; r <= rings; ++r) {
        const float theta = static_cast<float>(M_PI) * static_cast<float>(r) / rings;
        for (uint32_t s = 0; s < segments; ++s) {
            const float phi = 2.0f * static_cast<float>(M_PI) * static_cast<float>(s) / segments;
            mesh.addVertex(center + radius * glm::vec3(std::sin(theta) * std::cos(phi),
                                                       std::cos(theta),
                                                       std::sin(theta) * std::sin(phi)));
        }
    }
    for (uint32_t r = 0; r < rings; ++r) {
        for (uint32_t s = 0; s < segments; ++s) {
            const uint32_t a = r * segments + s;
            const uint32_t b = r * segments + (s + 1) % segments;
            const uint32_t c = a + segments;
            const uint32_t d = b + segments;
            mesh.addTriangle(a, c, b);
            mesh.addTriangle(b, c, d);
        }
    }
    return mesh;
}

// n x n unit quads in the plane z = 0 with integer corners, two triangles each.
Mesh grid(uint32_t n) {
    Mesh mesh;
    for (uint32_t y = 0; y <= n; ++y) {
        for (uint32_t x = 0; x <= n; ++x) {
            mesh.addVertex(glm::vec3(static_cast<float>(x), static_cast<float>(y), 0.0f));
        }
    }
    for (uint32_t y = 0; y < n; ++y) {
        for (uint32_t x = 0; x < n; ++x) {
            const uint32_t a = y * (n + 1) + x;
            mesh.addTriangle(a, a + 1, a + n + 2);
            mesh.addTriangle(a, a + n + 2, a + n + 1);
        }
    }
    return mesh;
}

struct TestRay {
    glm::vec3 origin;
    glm::vec3 dir;
};

// Four kinds of rays, in turn: random origin (inside or outside the mesh bounds) and random
// direction; aimed at a random point of a random triangle from a random distance with a random
// direction; the same with one direction component set to +0 or -0; the same along an axis.
std::vector<TestRay> randomRays(const Mesh& mesh, uint32_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    glm::vec3 lo;
    glm::vec3 hi;
    mesh.bounds(lo, hi);
    const glm::vec3 margin = 0.5f * (hi - lo) + glm::vec3(0.1f);
    const float reach = glm::length(hi - lo) + 0.1f;
    std::vector<TestRay> rays(count);
    for (uint32_t i = 0; i < count; ++i) {
        if (i % 4 == 0) {
            rays[i] = {uniformIn(rng, lo - margin, hi + margin), randomDirection(rng)};
            continue;
        }
        const auto triangle = static_cast<uint32_t>(rng() % mesh.triangles.size());
        float b1 = unit(rng);
        float b2 = unit(rng);
        if (b1 + b2 > 1.0f) {
            b1 = 1.0f - b1;
            b2 = 1.0f - b2;
        }
        const glm::vec3 target = (1.0f - b1 - b2) * mesh.position(triangle, 0) +
                                 b1 * mesh.position(triangle, 1) + b2 * mesh.position(triangle, 2);
        glm::vec3 d = randomDirection(rng);
        if (i % 4 == 2) {
            d[rng() % 3] = (rng() % 2) ? 0.0f : -0.0f;
        } else if (i % 4 == 3) {
            const auto axis = static_cast<int>(rng() % 3);
            d = glm::vec3((rng() % 2) ? 0.0f : -0.0f);
            d[axis] = (rng() % 2) ? 1.0f : -1.0f;
        }
        rays[i] = {target - reach * unit(rng) * d, d};
    }
    return rays;
}

std::vector<gpu::IsectTriangle> isectTriangles(const Mesh& mesh) {
    std::vector<gpu::IsectTriangle> tris;
    for (uint32_t i = 0; i < mesh.triangles.size(); ++i) {
        tris.push_back(
            makeIsectTriangle(mesh.position(i, 0), mesh.position(i, 1), mesh.position(i, 2), i));
    }
    return tris;
}

bool bruteClosest(const std::vector<gpu::IsectTriangle>& tris, const TestRay& ray, float tMax,
                  gpu::Hit& hit) {
    hit = {tMax, gpu::BVH_NO_HIT, 0.0f, 0.0f};
    bool found = false;
    for (const gpu::IsectTriangle& tri : tris) {
        found |= intersectTriangle(tri, ray.origin, ray.dir, hit);
    }
    return found;
}

// Closest hits and any-hits of the BVH must equal brute force over the same triangles.
// Ties (several triangles at the same t, e.g. a shared edge) may resolve to either triangle.
void expectMatchesBruteForce(const Mesh& mesh, const Bvh& bvh, const std::vector<TestRay>& rays,
                             uint32_t seed) {
    const std::vector<gpu::IsectTriangle> tris = isectTriangles(mesh);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    uint32_t hits = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const TestRay& ray = rays[i];
        gpu::Hit expected;
        gpu::Hit actual;
        const bool bruteHit = bruteClosest(tris, ray, INFINITY, expected);
        const bool bvhHit = bvh.traceClosest(ray.origin, ray.dir, INFINITY, actual);
        ASSERT_EQ(bvhHit, bruteHit) << "ray " << i;
        if (!bruteHit) {
            EXPECT_EQ(actual.triangle, gpu::BVH_NO_HIT);
            EXPECT_EQ(actual.t, INFINITY);
            EXPECT_FALSE(bvh.traceAny(ray.origin, ray.dir, INFINITY)) << "ray " << i;
            continue;
        }
        ++hits;
        if (actual.triangle == expected.triangle) {
            EXPECT_EQ(actual.t, expected.t) << "ray " << i;
            EXPECT_EQ(actual.b1, expected.b1) << "ray " << i;
            EXPECT_EQ(actual.b2, expected.b2) << "ray " << i;
        } else {
            ASSERT_NEAR(actual.t, expected.t, 1e-6f * expected.t) << "ray " << i;
            gpu::Hit alone{INFINITY, gpu::BVH_NO_HIT, 0.0f, 0.0f};
            ASSERT_TRUE(intersectTriangle(tris[actual.triangle], ray.origin, ray.dir, alone));
            EXPECT_EQ(alone.t, actual.t) << "ray " << i;
        }

        // Any-hit for a random tMax around the closest hit, and at the hit itself.
        const float tMax = expected.t * 2.0f * unit(rng);
        gpu::Hit limited;
        EXPECT_EQ(bvh.traceAny(ray.origin, ray.dir, tMax), bruteClosest(tris, ray, tMax, limited))
            << "ray " << i << " tMax " << tMax;
        EXPECT_TRUE(bvh.traceAny(ray.origin, ray.dir, INFINITY)) << "ray " << i;
        // The closest hit itself is excluded by 0 < t < tMax; a tie may still report a hit.
        if (bvh.traceAny(ray.origin, ray.dir, actual.t)) {
            EXPECT_TRUE(bruteClosest(tris, ray, actual.t, limited)) << "ray " << i;
        }
        gpu::Hit closestBelow;
        EXPECT_EQ(bvh.traceClosest(ray.origin, ray.dir, tMax, closestBelow), expected.t < tMax);
    }
    // Most rays are aimed at triangles (see randomRays), so many must hit.
    EXPECT_GT(hits, rays.size() / 4);
}

// Structure: every node reachable once, children after parents and inside parent bounds,
// leaves of 1..BVH_MAX_LEAF_TRIANGLES covering each triangle exactly once, depth within the
// cap, and every IsectTriangle equal to the original triangle it names.
void expectValidStructure(const Mesh& mesh, const Bvh& bvh) {
    const std::vector<gpu::BvhNode>& nodes = bvh.nodes();
    const std::vector<gpu::IsectTriangle>& tris = bvh.triangles();
    const size_t n = mesh.triangles.size();
    ASSERT_EQ(tris.size(), n);
    std::vector<int> nodeSeen(nodes.size(), 0);
    std::vector<int> slotSeen(n, 0);
    std::vector<int> triangleSeen(n, 0);
    struct Item {
        uint32_t node;
        uint32_t depth;
    };
    std::vector<Item> todo{{0, 0}};
    uint32_t maxDepth = 0;
    size_t leaves = 0;
    while (!todo.empty()) {
        const Item item = todo.back();
        todo.pop_back();
        ASSERT_LT(item.node, nodes.size());
        ASSERT_EQ(nodeSeen[item.node]++, 0) << "node " << item.node << " reached twice";
        const gpu::BvhNode& node = nodes[item.node];
        maxDepth = std::max(maxDepth, item.depth);
        if (node.count > 0) {
            ++leaves;
            ASSERT_LE(node.count, gpu::BVH_MAX_LEAF_TRIANGLES);
            ASSERT_LE(size_t{node.leftOrFirst} + node.count, n);
            for (uint32_t i = node.leftOrFirst; i < node.leftOrFirst + node.count; ++i) {
                ++slotSeen[i];
                const auto original = std::bit_cast<uint32_t>(tris[i].v0.w);
                ASSERT_LT(original, n);
                ++triangleSeen[original];
                const gpu::IsectTriangle ref =
                    makeIsectTriangle(mesh.position(original, 0), mesh.position(original, 1),
                                      mesh.position(original, 2), original);
                EXPECT_EQ(std::memcmp(&ref, &tris[i], sizeof(ref)), 0);
                for (int corner = 0; corner < 3; ++corner) {
                    const glm::vec3 p = mesh.position(original, corner);
                    EXPECT_TRUE(glm::all(glm::lessThanEqual(node.boundsMin, p)));
                    EXPECT_TRUE(glm::all(glm::lessThanEqual(p, node.boundsMax)));
                }
            }
        } else {
            ASSERT_GT(node.leftOrFirst, item.node);
            ASSERT_LT(size_t{node.leftOrFirst} + 1, nodes.size());
            for (uint32_t child = node.leftOrFirst; child <= node.leftOrFirst + 1; ++child) {
                EXPECT_TRUE(glm::all(glm::lessThanEqual(node.boundsMin, nodes[child].boundsMin)));
                EXPECT_TRUE(glm::all(glm::lessThanEqual(nodes[child].boundsMax, node.boundsMax)));
                todo.push_back({child, item.depth + 1});
            }
        }
    }
    EXPECT_EQ(leaves * 2 - 1, nodes.size());
    for (size_t i = 0; i < nodes.size(); ++i) {
        EXPECT_EQ(nodeSeen[i], 1) << "node " << i;
    }
    for (size_t i = 0; i < n; ++i) {
        EXPECT_EQ(slotSeen[i], 1) << "slot " << i;
        EXPECT_EQ(triangleSeen[i], 1) << "triangle " << i;
    }
    EXPECT_LE(maxDepth, gpu::BVH_MAX_DEPTH);
    EXPECT_EQ(maxDepth, bvh.depth());
}

void expectBvhCorrect(const Mesh& mesh, uint32_t rayCount, uint32_t seed) {
    const Bvh bvh = Bvh::build(mesh.vertices, mesh.triangles, "test");
    expectValidStructure(mesh, bvh);
    expectMatchesBruteForce(mesh, bvh, randomRays(mesh, rayCount, seed), seed + 1);
}

TEST(Bvh, RandomSoupMatchesBruteForce) {
    for (const uint32_t count : {2u, 3u, 5u, 17u, 100u, 2000u}) {
        SCOPED_TRACE(count);
        expectBvhCorrect(randomSoup(count, 7 + count), 3000, 11 + count);
    }
}

TEST(Bvh, SphereMatchesBruteForce) {
    Mesh mesh = sphere(48, 96, 1.0f, glm::vec3(0.3f, -0.2f, 0.1f));
    const Mesh inner = sphere(12, 24, 0.4f, glm::vec3(0.2f, -0.1f, 0.0f));
    const auto base = static_cast<uint32_t>(mesh.vertices.size());
    mesh.vertices.insert(mesh.vertices.end(), inner.vertices.begin(), inner.vertices.end());
    for (const gpu::Triangle& t : inner.triangles) {
        mesh.addTriangle(base + t.i0, base + t.i1, base + t.i2);
    }
    expectBvhCorrect(mesh, 5000, 3);
}

// deviceTexels: the kernels' serialization (shared/scene_types.h) of the binary tree collapsed
// to 4-wide nodes. Walks the binary tree and the wide nodes together: each wide node holds the
// grandchildren of its binary node (a child itself where that is a leaf), with their bounds bit
// for bit, refs to their wide nodes or triangles, unused slots empty; every wide node is
// reached once, the triangles follow bit for bit, and leaves lie below ceil(depth / 2) wide
// nodes (the traversal's stack bound, BVH_STACK_SIZE). Returns the most wide nodes above a leaf.
uint32_t expectWideTexels(const Bvh& bvh) {
    const std::vector<glm::uvec4> texels = bvh.deviceTexels();
    const std::vector<gpu::BvhNode>& nodes = bvh.nodes();
    const size_t triangleBase = texels.size() - gpu::BVH_TRIANGLE_TEXELS * bvh.triangles().size();
    EXPECT_EQ(triangleBase % gpu::BVH_NODE_TEXELS, 0u);
    std::vector<int> reached(triangleBase / gpu::BVH_NODE_TEXELS, 0);
    uint32_t wideDepth = 0;
    // The wide node at `address` for binary node `node`, `above` wide nodes above it.
    auto walk = [&](auto&& self, size_t address, uint32_t node, uint32_t above) -> void {
        ASSERT_EQ(address % gpu::BVH_NODE_TEXELS, 0u);
        ASSERT_LT(address, triangleBase);
        ++reached[address / gpu::BVH_NODE_TEXELS];
        std::vector<uint32_t> kids;
        const gpu::BvhNode& n = nodes[node];
        if (n.count > 0) {
            kids.push_back(node);
        } else {
            for (const uint32_t c : {n.leftOrFirst, n.leftOrFirst + 1}) {
                if (nodes[c].count > 0) {
                    kids.push_back(c);
                } else {
                    kids.push_back(nodes[c].leftOrFirst);
                    kids.push_back(nodes[c].leftOrFirst + 1);
                }
            }
        }
        for (uint32_t k = 0; k < gpu::BVH_WIDTH; ++k) {
            const uint32_t ref = texels[address + gpu::BVH_NODE_REFS_TEXEL][k];
            if (k >= kids.size()) {
                EXPECT_EQ(ref, gpu::BVH_EMPTY_CHILD) << "address " << address << " slot " << k;
                continue;
            }
            const gpu::BvhNode& c = nodes[kids[k]];
            for (int axis = 0; axis < 3; ++axis) {
                EXPECT_EQ(texels[address + axis][k], std::bit_cast<uint32_t>(c.boundsMin[axis]));
                EXPECT_EQ(texels[address + 3 + axis][k], std::bit_cast<uint32_t>(c.boundsMax[axis]));
            }
            EXPECT_EQ(ref & 7u, c.count);
            if (c.count > 0) {
                EXPECT_EQ(ref >> 3, triangleBase + 3 * size_t{c.leftOrFirst});
                wideDepth = std::max(wideDepth, above + 1);
            } else {
                self(self, ref >> 3, kids[k], above + 1);
            }
        }
    };
    walk(walk, 0, 0, 0);
    for (size_t w = 0; w < reached.size(); ++w) EXPECT_EQ(reached[w], 1) << "wide node " << w;
    for (size_t i = 0; i < bvh.triangles().size(); ++i) {
        const gpu::IsectTriangle& t = bvh.triangles()[i];
        EXPECT_EQ(std::memcmp(&texels[triangleBase + 3 * i], &t, sizeof(t)), 0) << "triangle " << i;
    }
    EXPECT_EQ(wideDepth, (bvh.depth() + 1) / 2 + (bvh.depth() == 0 ? 1 : 0));
    EXPECT_LE(wideDepth, gpu::BVH_MAX_DEPTH / 2);
    return wideDepth;
}

TEST(Bvh, DeviceTexelsSerializeTheWideTree) {
    const Mesh mesh = randomSoup(300, 5);
    expectWideTexels(Bvh::build(mesh.vertices, mesh.triangles, "test"));
    // Odd and even binary depths, and a single leaf (the wide root's one child).
    const Mesh soup = randomSoup(1500, 21);
    EXPECT_EQ(expectWideTexels(Bvh::build(soup.vertices, soup.triangles, "soup", 11)), 6u);
    EXPECT_EQ(expectWideTexels(Bvh::build(soup.vertices, soup.triangles, "soup", 10)), 5u);
    const Mesh one = randomSoup(1, 3);
    EXPECT_EQ(expectWideTexels(Bvh::build(one.vertices, one.triangles, "one")), 1u);
}

TEST(Bvh, GridMatchesBruteForce) {
    expectBvhCorrect(grid(40), 5000, 5);
}

// Rays along -z through grid vertices and edge midpoints, where several triangles meet:
// inclusive edges must not let them through.
TEST(Bvh, GridSharedEdgesAndVerticesAreHit) {
    const Mesh mesh = grid(8);
    const Bvh bvh = Bvh::build(mesh.vertices, mesh.triangles, "grid");
    for (int y = 0; y <= 16; ++y) {
        for (int x = 0; x <= 16; ++x) {
            const glm::vec3 origin(0.5f * static_cast<float>(x), 0.5f * static_cast<float>(y),
                                   3.0f);
            gpu::Hit hit;
            ASSERT_TRUE(bvh.traceClosest(origin, glm::vec3(0.0f, 0.0f, -1.0f), INFINITY, hit))
                << x << "," << y;
            EXPECT_EQ(hit.t, 3.0f);
            EXPECT_TRUE(bvh.traceAny(origin, glm::vec3(0.0f, 0.0f, -1.0f), 3.5f));
            EXPECT_FALSE(bvh.traceAny(origin, glm::vec3(0.0f, 0.0f, -1.0f), 3.0f));
        }
    }
}

TEST(Bvh, HitReportsOriginalTriangleAndBarycentrics) {
    Mesh mesh = randomSoup(50, 1);
    mesh.addTriangle(glm::vec3(10, 0, 0), glm::vec3(12, 0, 0), glm::vec3(10, 4, 0));
    const Bvh bvh = Bvh::build(mesh.vertices, mesh.triangles, "test");
    gpu::Hit hit;
    ASSERT_TRUE(bvh.traceClosest(glm::vec3(10.5f, 1.0f, 2.0f), glm::vec3(0, 0, -2), 10.0f, hit));
    EXPECT_EQ(hit.triangle, 50u);
    EXPECT_FLOAT_EQ(hit.t, 1.0f);
    EXPECT_FLOAT_EQ(hit.b1, 0.25f);
    EXPECT_FLOAT_EQ(hit.b2, 0.25f);
    // Back faces are hit too, and the miss result is fully defined.
    ASSERT_TRUE(bvh.traceClosest(glm::vec3(10.5f, 1.0f, -2.0f), glm::vec3(0, 0, 1), 10.0f, hit));
    EXPECT_EQ(hit.triangle, 50u);
    EXPECT_FALSE(bvh.traceClosest(glm::vec3(10.5f, 1.0f, -2.0f), glm::vec3(0, 0, 1), 1.5f, hit));
    EXPECT_EQ(hit.t, 1.5f);
    EXPECT_EQ(hit.triangle, gpu::BVH_NO_HIT);
}

TEST(Bvh, SingleTriangle) {
    Mesh mesh;
    mesh.addTriangle(glm::vec3(0, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
    const Bvh bvh = Bvh::build(mesh.vertices, mesh.triangles, "one");
    ASSERT_EQ(bvh.nodes().size(), 1u);
    EXPECT_EQ(bvh.nodes()[0].count, 1u);
    EXPECT_EQ(bvh.depth(), 0u);
    expectBvhCorrect(mesh, 2000, 9);
}

// Many copies of one triangle: every centroid coincides, so no SAH plane exists.
TEST(Bvh, IdenticalCentroids) {
    Mesh mesh;
    for (int i = 0; i < 1000; ++i) {
        mesh.addTriangle(glm::vec3(0, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
    }
    const Bvh bvh = Bvh::build(mesh.vertices, mesh.triangles, "copies");
    expectValidStructure(mesh, bvh);
    EXPECT_LE(bvh.depth(), 10u);  // object median splits: log2(1000 / 4) rounded up
    expectMatchesBruteForce(mesh, bvh, randomRays(mesh, 2000, 4), 5);
}

// Nested triangles of growing size sharing one centroid.
TEST(Bvh, SharedCentroidDifferentSizes) {
    Mesh mesh;
    for (int i = 1; i <= 200; ++i) {
        const float s = 0.01f * static_cast<float>(i);
        mesh.addTriangle(glm::vec3(-s, -s, 0.001f * i), glm::vec3(s, -s, 0), glm::vec3(0, s, 0));
    }
    expectBvhCorrect(mesh, 2000, 6);
}

// Zero-area triangles (collinear corners, repeated corners) are kept but never hit.
TEST(Bvh, DegenerateTriangles) {
    Mesh mesh = randomSoup(200, 2);
    std::mt19937 rng(3);
    for (int i = 0; i < 200; ++i) {
        const glm::vec3 a = uniformIn(rng, glm::vec3(-5.0f), glm::vec3(5.0f));
        const glm::vec3 b = uniformIn(rng, glm::vec3(-5.0f), glm::vec3(5.0f));
        if (i % 2 == 0) {
            mesh.addTriangle(a, a, a);
        } else {
            mesh.addTriangle(a, b, a);
        }
    }
    expectBvhCorrect(mesh, 3000, 8);

    // Only points: every node box has zero area.
    Mesh points;
    for (int i = 0; i < 50; ++i) {
        const glm::vec3 a = uniformIn(rng, glm::vec3(-1.0f), glm::vec3(1.0f));
        points.addTriangle(a, a, a);
    }
    const Bvh bvh = Bvh::build(points.vertices, points.triangles, "points");
    expectValidStructure(points, bvh);
    gpu::Hit hit;
    for (const TestRay& ray : randomRays(points, 500, 4)) {
        EXPECT_FALSE(bvh.traceClosest(ray.origin, ray.dir, INFINITY, hit));
        EXPECT_FALSE(bvh.traceAny(ray.origin, ray.dir, INFINITY));
    }
}

// A lower cap than the SAH tree needs: SAH gives way to median splits near the cap, and
// leaves stay within BVH_MAX_LEAF_TRIANGLES. A cap below what 4-triangle leaves allow is raised.
TEST(Bvh, DepthCap) {
    const Mesh mesh = randomSoup(1500, 21);
    const Bvh free = Bvh::build(mesh.vertices, mesh.triangles, "soup");
    EXPECT_LE(free.depth(), gpu::BVH_MAX_DEPTH);
    ASSERT_GT(free.depth(), 11u);
    const std::vector<TestRay> rays = randomRays(mesh, 1500, 22);
    for (const uint32_t cap : {11u, 10u}) {
        const Bvh capped = Bvh::build(mesh.vertices, mesh.triangles, "soup", cap);
        expectValidStructure(mesh, capped);
        EXPECT_EQ(capped.depth(), cap);
        expectMatchesBruteForce(mesh, capped, rays, 23);
    }
    // 1500 / 4 = 375 leaves need depth ceil(log2(375)) = 9.
    const Bvh lowest = Bvh::build(mesh.vertices, mesh.triangles, "soup", 1);
    expectValidStructure(mesh, lowest);
    EXPECT_EQ(lowest.depth(), 9u);
    expectMatchesBruteForce(mesh, lowest, rays, 24);
}

// Slivers get zero edges (never hit); thin but sound triangles keep theirs.
TEST(Bvh, SliversAreNeverHit) {
    const glm::vec3 a(0.3f, -0.2f, 0.1f);
    const gpu::IsectTriangle sliver = makeIsectTriangle(
        a, a + glm::vec3(1.0f, 0.5f, 0.25f), a + glm::vec3(1.0f, 0.5f, 0.25f + 1e-7f), 0);
    EXPECT_EQ(glm::vec3(sliver.e1), glm::vec3(0.0f));
    EXPECT_EQ(glm::vec3(sliver.e2), glm::vec3(0.0f));
    gpu::Hit hit{INFINITY, gpu::BVH_NO_HIT, 0.0f, 0.0f};
    EXPECT_FALSE(intersectTriangle(sliver, a + glm::vec3(0.5f, 0.25f, 2.0f),
                                   glm::vec3(0.0f, 0.0f, -1.0f), hit));

    const gpu::IsectTriangle thin = makeIsectTriangle(glm::vec3(0.0f), glm::vec3(1.0f, 0.0f, 0.0f),
                                                      glm::vec3(1.0f, 1e-3f, 0.0f), 7);
    ASSERT_EQ(glm::vec3(thin.e2), glm::vec3(1.0f, 1e-3f, 0.0f));
    EXPECT_TRUE(
        intersectTriangle(thin, glm::vec3(0.9f, 0.0005f, 1.0f), glm::vec3(0.0f, 0.0f, -1.0f), hit));
    EXPECT_EQ(hit.triangle, 7u);
}

TEST(Bvh, RejectsBadInput) {
    Mesh mesh;
    EXPECT_THROW(Bvh::build(mesh.vertices, mesh.triangles, "empty.gltf"), Error);
    mesh.addTriangle(glm::vec3(0, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
    mesh.triangles[0].i2 = 3;
    try {
        Bvh::build(mesh.vertices, mesh.triangles, "bad.gltf");
        FAIL() << "expected pmcr::Error";
    } catch (const Error& e) {
        EXPECT_STREQ(e.what(), "bad.gltf: triangle 0 uses vertex 3 of 3");
    }
    mesh.triangles[0].i2 = 2;
    mesh.vertices[1].position.y = NAN;
    try {
        Bvh::build(mesh.vertices, mesh.triangles, "nan.gltf");
        FAIL() << "expected pmcr::Error";
    } catch (const Error& e) {
        EXPECT_STREQ(e.what(), "nan.gltf: vertex 1 has a non-finite position");
    }
    Scene scene;
    scene.path = "scenes/none.gltf";
    try {
        Bvh::build(scene);
        FAIL() << "expected pmcr::Error";
    } catch (const Error& e) {
        EXPECT_STREQ(e.what(), "scenes/none.gltf: no triangles to build a BVH over");
    }
}

// About 200k triangles: a bumpy sphere (Lat-long, 316 x 316 quads) on a ground grid.
Mesh benchmarkMesh() {
    Mesh mesh;
    const uint32_t rings = 300;
    const uint32_t segments = 316;
    for (uint32_t r = 0; r <= rings; ++r) {
        const float theta = static_cast<float>(M_PI) * static_cast<float>(r) / rings;
        for (uint32_t s = 0; s < segments; ++s) {
            const float phi = 2.0f * static_cast<float>(M_PI) * static_cast<float>(s) / segments;
            const glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                              std::sin(theta) * std::sin(phi));
            const float bump = 1.0f + 0.08f * std::sin(9.0f * phi) * std::sin(7.0f * theta) +
                               0.03f * std::sin(37.0f * phi + 11.0f * theta);
            mesh.addVertex(glm::vec3(0.0f, 1.0f, 0.0f) + bump * n);
        }
    }
    for (uint32_t r = 0; r < rings; ++r) {
        for (uint32_t s = 0; s < segments; ++s) {
            const uint32_t a = r * segments + s;
            const uint32_t b = r * segments + (s + 1) % segments;
            mesh.addTriangle(a, a + segments, b);
            mesh.addTriangle(b, a + segments, b + segments);
        }
    }
    const auto base = static_cast<uint32_t>(mesh.vertices.size());
    const uint32_t n = 80;
    for (uint32_t y = 0; y <= n; ++y) {
        for (uint32_t x = 0; x <= n; ++x) {
            mesh.addVertex(glm::vec3(-4.0f + 8.0f * x / n, 0.0f, -4.0f + 8.0f * y / n));
        }
    }
    for (uint32_t y = 0; y < n; ++y) {
        for (uint32_t x = 0; x < n; ++x) {
            const uint32_t a = base + y * (n + 1) + x;
            mesh.addTriangle(a, a + n + 2, a + 1);
            mesh.addTriangle(a, a + n + 1, a + n + 2);
        }
    }
    return mesh;
}

TEST(Bvh, DISABLED_Throughput) {
    const Mesh mesh = benchmarkMesh();
    auto start = std::chrono::steady_clock::now();
    const Bvh bvh = Bvh::build(mesh.vertices, mesh.triangles, "benchmark");
    const double buildSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("%zu triangles: build %.1f ms, %zu nodes, depth %u\n", mesh.triangles.size(),
                buildSeconds * 1e3, bvh.nodes().size(), bvh.depth());

    // Camera rays in scanline order (coherent) and random rays (incoherent).
    const uint32_t width = 1024;
    const uint32_t height = 768;
    std::vector<TestRay> camera;
    const glm::vec3 eye(0.0f, 1.5f, 4.0f);
    const glm::vec3 forward = glm::normalize(glm::vec3(0.0f, 1.0f, 0.0f) - eye);
    const glm::vec3 right = glm::normalize(glm::cross(forward, glm::vec3(0, 1, 0)));
    const glm::vec3 up = glm::cross(right, forward);
    const float tanHalf = 0.5f;
    for (uint32_t y = 0; y < height; ++y) {
        for (uint32_t x = 0; x < width; ++x) {
            const float px = (2.0f * (x + 0.5f) / width - 1.0f) * tanHalf * width / height;
            const float py = (1.0f - 2.0f * (y + 0.5f) / height) * tanHalf;
            camera.push_back({eye, glm::normalize(forward + px * right + py * up)});
        }
    }
    std::vector<TestRay> random(camera.size());
    std::mt19937 rng(1);
    for (TestRay& ray : random) {
        ray = {uniformIn(rng, glm::vec3(-2.0f, 0.0f, -2.0f), glm::vec3(2.0f, 2.5f, 2.0f)),
               randomDirection(rng)};
    }

    const auto measure = [&](const char* name, const std::vector<TestRay>& rays) {
        uint32_t hits = 0;
        start = std::chrono::steady_clock::now();
        for (const TestRay& ray : rays) {
            gpu::Hit hit;
            hits += bvh.traceClosest(ray.origin, ray.dir, INFINITY, hit) ? 1 : 0;
        }
        const double closest =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        uint32_t occluded = 0;
        start = std::chrono::steady_clock::now();
        for (const TestRay& ray : rays) {
            occluded += bvh.traceAny(ray.origin, ray.dir, INFINITY) ? 1 : 0;
        }
        const double any =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::printf("%-10s closest %6.2f Mrays/s (%u hits)   any %6.2f Mrays/s (%u)\n", name,
                    rays.size() / closest * 1e-6, hits, rays.size() / any * 1e-6, occluded);
    };
    measure("coherent", camera);
    measure("incoherent", random);
}

}  // namespace
}  // namespace pmcr
