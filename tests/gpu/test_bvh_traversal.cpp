// shaders/common/bvh.glsl against the host's scalar traversal (Bvh::traceClosest, traceAny),
// which tests/host/test_bvh.cpp checks against brute force: the same rays, traced through the
// same tree (the host's binary nodes, the kernels' 4-wide form of them) by
// shaders/tests/bvh_trace_test.comp, must give the same closest hits and the same occlusion
// answers. The GLSL uses the same intersection arithmetic as the C++, but visits triangles in
// another order and the device compiler may contract or reorder float operations, so a hit
// counts as the same when it names the same triangle, or (at a shared edge) both hit at the
// same distance. Every ray must agree, except a rare ray that grazes a triangle within float
// rounding (grazes(): lavapipe and the host round alike, NVIDIA's compiler fuses multiply-adds
// and decides two of the dragon's 20000 rays otherwise). The dragon's deep traversals store entries of the stack
// beyond its eight registers, several in one step (bvhPush), which these tests would catch
// losing one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "gpu_test.h"
#include "render/gpu_scene.h"
#include "scene/gltf_loader.h"
#include "scene/scene.h"
#include "test_util.h"

namespace pmcr::test {
namespace {

struct TracePush {
    uint32_t count;
};

// shaders/bench/trace_rays.comp's push constants.
struct RayListPush {
    uint32_t count;
    uint32_t anyHit;
    uint32_t raysPerInvocation;
};

glm::vec3 randomDirection(std::mt19937& rng) {
    std::normal_distribution<float> n(0.0f, 1.0f);
    for (;;) {
        const glm::vec3 d(n(rng), n(rng), n(rng));
        if (glm::dot(d, d) > 1e-6f) return glm::normalize(d);
    }
}

glm::vec3 uniformIn(std::mt19937& rng, const glm::vec3& lo, const glm::vec3& hi) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    return lo + (hi - lo) * glm::vec3(u(rng), u(rng), u(rng));
}

// Triangles of random size and orientation in a box, one of them emissive (finalizeScene wants
// a light).
Scene randomSoup(uint32_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> size(0.01f, 0.5f);
    Scene s;
    s.path = "bvh-soup.gltf";
    gpu::Material m{};
    m.baseColor = glm::vec3(0.5f);
    m.baseColorTexture = -1;
    m.roughness = 1.0f;
    m.ior = 1.5f;
    s.materials = {m, m};
    s.materials[1].emission = glm::vec3(1.0f);
    for (uint32_t i = 0; i < count; ++i) {
        const glm::vec3 c = uniformIn(rng, glm::vec3(-5.0f), glm::vec3(5.0f));
        const float r = size(rng);
        const uint32_t base = uint32_t(s.vertices.size());
        for (int k = 0; k < 3; ++k) {
            gpu::Vertex v{};
            v.position = c + r * randomDirection(rng);
            s.vertices.push_back(v);
        }
        s.triangles.push_back({base, base + 1, base + 2, i == 0 ? 1u : 0u});
    }
    s.cameras.push_back(Camera{});
    finalizeScene(s);
    return s;
}

// As tests/host/test_bvh.cpp: a quarter of the rays from random points in and around the
// bounds in random directions, the rest aimed at random points of random triangles, some of
// them with a +-0 direction component or along an axis. Every fourth ray gets a finite tMax
// short of its target (shadow-ray style) so that tMax is exercised too.
std::vector<gpu::BvhQuery> randomRays(const Scene& scene, uint32_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const glm::vec3 lo = scene.boundsMin, hi = scene.boundsMax;
    const glm::vec3 margin = 0.5f * (hi - lo) + glm::vec3(0.1f);
    const float reach = glm::length(hi - lo) + 0.1f;
    std::vector<gpu::BvhQuery> rays(count);
    for (uint32_t i = 0; i < count; ++i) {
        gpu::BvhQuery q{};
        q.tMax = 1e30f;
        if (i % 4 == 0) {
            q.origin = uniformIn(rng, lo - margin, hi + margin);
            q.direction = randomDirection(rng);
            rays[i] = q;
            continue;
        }
        const gpu::Triangle& t = scene.triangles[rng() % scene.triangles.size()];
        float b1 = unit(rng), b2 = unit(rng);
        if (b1 + b2 > 1.0f) {
            b1 = 1.0f - b1;
            b2 = 1.0f - b2;
        }
        const glm::vec3 target = (1.0f - b1 - b2) * scene.vertices[t.i0].position +
                                 b1 * scene.vertices[t.i1].position +
                                 b2 * scene.vertices[t.i2].position;
        glm::vec3 d = randomDirection(rng);
        if (i % 4 == 2) {
            d[rng() % 3] = (rng() % 2) ? 0.0f : -0.0f;
            if (glm::dot(d, d) < 1e-6f) d = glm::vec3(1.0f, 0.0f, 0.0f);
        } else if (i % 4 == 3) {
            const int axis = int(rng() % 3);
            d = glm::vec3((rng() % 2) ? 0.0f : -0.0f);
            d[axis] = (rng() % 2) ? 1.0f : -1.0f;
        }
        const float distance = reach * unit(rng);
        q.origin = target - distance * d;
        q.direction = d;
        if (i % 8 == 1) q.tMax = std::max(1e-3f, 0.999f * distance);
        rays[i] = q;
    }
    return rays;
}

// Whether ray q grazes triangle `index`: crosses its plane within float rounding of its edges,
// where another rounding of the same arithmetic (a compiler that fuses multiply-adds, as
// NVIDIA's does, where lavapipe and the host do not) may decide hit or miss the other way.
// The division-free test's numerators are dot products of terms of size |s| |e| (s: origin to
// v0, e: the longer edge), so in float they are good to about eps |s| |e|; over det = |e1 x e2|
// cos(ray, normal) that is a barycentric error of eps |s| |e| / det, large for small triangles
// seen from afar or nearly edge-on. A ray grazes when its barycentric margin (the smallest
// coordinate, in double precision) is within kGrazingUlps such errors of 0.
bool grazes(const Scene& scene, const gpu::BvhQuery& q, uint32_t index) {
    constexpr double kGrazingUlps = 8.0;
    const gpu::Triangle& tri = scene.triangles[index];
    const glm::dvec3 v0(scene.vertices[tri.i0].position), v1(scene.vertices[tri.i1].position),
        v2(scene.vertices[tri.i2].position);
    const glm::dvec3 o(q.origin), d = glm::normalize(glm::dvec3(q.direction));
    const glm::dvec3 e1 = v1 - v0, e2 = v2 - v0, p = glm::cross(d, e2), s = o - v0,
                     r = glm::cross(s, e1);
    const double det = glm::dot(e1, p);
    if (det == 0.0) return true;  // edge-on
    const double u = glm::dot(s, p) / det, v = glm::dot(d, r) / det;
    const double margin = std::min({u, v, 1.0 - u - v});
    const double error = std::ldexp(1.0, -24) * glm::length(s) *
                         std::max(glm::length(e1), glm::length(e2)) / std::abs(det);
    return std::abs(margin) <= kGrazingUlps * error;
}

bool sameHit(const gpu::Hit& a, const gpu::Hit& b) {
    if (a.triangle == b.triangle) {
        return a.triangle == gpu::BVH_NO_HIT ||
               std::abs(a.t - b.t) <= 1e-4f * std::max(1.0f, std::abs(a.t));
    }
    return a.triangle != gpu::BVH_NO_HIT && b.triangle != gpu::BVH_NO_HIT &&
           std::abs(a.t - b.t) <= 1e-5f * std::max(1.0f, std::abs(a.t));
}

class BvhTraversal : public GpuTest {
protected:
    // Traces `rays` on the device and on the host and compares closest hits and occlusion; at
    // most `maxMismatchFraction` of the rays may disagree. The device's any-hit answer must
    // also agree with its own closest hit.
    void expectMatchesHost(const Scene& scene, const std::vector<gpu::BvhQuery>& rays,
                           double maxMismatchFraction) {
        const GpuScene gpuScene(context(), layout(), scene, 0, 8, 8);
        const Bvh& bvh = gpuScene.bvh();
        const uint32_t n = uint32_t(rays.size());
        auto queries = storage(rays, "bvh queries");
        auto hits = zeros(size_t(n) * sizeof(gpu::Hit), "bvh hits");
        auto occluded = zeros(size_t(n) * sizeof(uint32_t), "bvh occluded");
        run("tests/bvh_trace_test", TracePush{n}, n, {&queries, &hits, &occluded},
            &gpuScene.descriptorSet());
        const auto gpuHits = hits.download<gpu::Hit>(n);
        const auto gpuOccluded = occluded.download<uint32_t>(n);

        uint32_t hitMismatches = 0, anyMismatches = 0, grazingMismatches = 0, hitCount = 0;
        for (uint32_t i = 0; i < n; ++i) {
            gpu::Hit cpu;
            const bool cpuHit = bvh.traceClosest(rays[i].origin, rays[i].direction,
                                                 rays[i].tMax, cpu);
            if (!cpuHit) cpu.triangle = gpu::BVH_NO_HIT;
            const bool cpuAny = bvh.traceAny(rays[i].origin, rays[i].direction, rays[i].tMax);
            hitCount += cpuHit;
            const gpu::Hit& g = gpuHits[i];
            bool grazing = false;
            if (!sameHit(cpu, g)) {
                // The nearer report is a triangle that the other side passed by: allowed only
                // where the ray grazes it.
                const bool gpuNearer =
                    g.triangle != gpu::BVH_NO_HIT && (cpu.triangle == gpu::BVH_NO_HIT || g.t < cpu.t);
                grazing = grazes(scene, rays[i], gpuNearer ? g.triangle : cpu.triangle);
            }
            if (grazing) {
                ++grazingMismatches;
            } else if (!sameHit(cpu, g)) {
                ++hitMismatches;
                if (hitMismatches <= 5)
                    ADD_FAILURE()
                        << "ray " << i << ": CPU triangle " << cpu.triangle << " t " << cpu.t
                        << ", GPU triangle " << g.triangle << " t " << g.t
                        << (hitMismatches == 5 ? " (further mismatches not listed)" : "");
            }
            anyMismatches += !grazing && (gpuOccluded[i] != 0u) != cpuAny;
            // On the device itself: any-hit must agree with closest-hit.
            EXPECT_EQ(gpuOccluded[i] != 0u, g.triangle != gpu::BVH_NO_HIT) << "ray " << i;
        }
        // Most rays are aimed at triangles, so many must hit, and some must miss.
        EXPECT_GT(hitCount, n / 2);
        EXPECT_LT(hitCount, n);
        EXPECT_LE(double(hitMismatches), maxMismatchFraction * n);
        EXPECT_LE(double(anyMismatches), maxMismatchFraction * n);
        // Grazing rays that another rounding decides otherwise are rare (2 of the dragon's
        // 20000 rays on an NVIDIA H200, none on lavapipe).
        EXPECT_LE(grazingMismatches, n / 1000);
        RecordProperty("closest_hit_mismatches", int(hitMismatches));
        RecordProperty("any_hit_mismatches", int(anyMismatches));
        RecordProperty("grazing_mismatches", int(grazingMismatches));
    }
};

TEST_F(BvhTraversal, RandomSoupMatchesHost) {
    for (const uint32_t count : {1u, 2u, 17u, 3000u}) {
        SCOPED_TRACE(count);
        const Scene scene = randomSoup(count, 5 + count);
        expectMatchesHost(scene, randomRays(scene, 8000, 3 + count), 0.0);
    }
}

// A shipped scene: closed spheres, shared edges of the box walls, and (for the camera's view)
// rays from outside.
TEST_F(BvhTraversal, DefaultSceneMatchesHost) {
    const Scene scene = loadScene(sourcePath("scenes/cornell-spheres.glb"));
    expectMatchesHost(scene, randomRays(scene, 20000, 9), 0.0);
}

// The largest scene (about 200k triangles, a deep BVH): the longest traversals pmcr runs. On
// lavapipe a traversal cut short by Mesa's loop budget (tests/gpu/test_loop_limits.cpp) would
// show up here as a GPU miss or a farther hit.
TEST_F(BvhTraversal, DragonMatchesHost) {
    const Scene scene = loadScene(sourcePath("scenes/dragon-direct.gltf"));
    ASSERT_GT(scene.triangles.size(), 200000u);
    expectMatchesHost(scene, randomRays(scene, 20000, 13), 0.0);
}

// Rays in turn (bvhBegin / bvhStep, shaders/bench/trace_rays.glsl): an invocation that traces
// several rays one after the other in one loop, its lanes starting their next ray as soon as
// the last ends, gives every ray the same answer, bit for bit, as one ray per invocation.
TEST_F(BvhTraversal, RaysInTurnMatchOneRayPerInvocation) {
    const Scene scene = loadScene(sourcePath("scenes/cornell-spheres.glb"));
    const GpuScene gpuScene(context(), layout(), scene, 0, 8, 8);
    const auto rays = randomRays(scene, 5000, 21);
    const uint32_t n = uint32_t(rays.size());
    auto queries = storage(rays, "bvh queries");
    for (const uint32_t anyHit : {0u, 1u}) {
        std::vector<std::vector<gpu::Hit>> results;
        for (const uint32_t perInvocation : {1u, 7u, 32u}) {
            auto hits = zeros(size_t(n) * sizeof(gpu::Hit), "bvh hits");
            run("bench/trace_rays", RayListPush{n, anyHit, perInvocation},
                (n + perInvocation - 1) / perInvocation, {&queries, &hits},
                &gpuScene.descriptorSet());
            results.push_back(hits.download<gpu::Hit>(n));
        }
        for (size_t k = 1; k < results.size(); ++k)
            for (uint32_t i = 0; i < n; ++i) {
                const gpu::Hit& a = results[0][i];
                const gpu::Hit& b = results[k][i];
                ASSERT_TRUE(a.t == b.t && a.triangle == b.triangle && a.b1 == b.b1 && a.b2 == b.b2)
                    << "anyHit " << anyHit << ", variant " << k << ", ray " << i;
            }
    }
}

}  // namespace
}  // namespace pmcr::test
