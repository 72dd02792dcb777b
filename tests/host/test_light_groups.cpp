// Lights as PMC-HI sees them (scene/scene.h buildLightGroups): emitters grouped by shared vertex
// positions, each group an alias table over its own triangles' power.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "scene/gltf_loader.h"
#include "scene/scene.h"
#include "scene_builder.h"
#include "test_util.h"

namespace pmcr {
namespace {

using test::addTriangle;
using test::testMaterial;

// Checks group g's alias table: pmfs summing to 1, the alias table reproducing them, and the
// group's power the sum of its triangles'. Returns its triangles.
std::vector<uint32_t> expectAliasTable(const Scene& scene, const LightGroupTable& t,
                                       const gpu::LightGroup& g) {
    std::vector<uint32_t> triangles;
    if (g.firstEmitter + g.emitterCount > t.emitters.size()) {
        ADD_FAILURE() << "group past the end of the emitter table";
        return triangles;
    }
    double pmfSum = 0.0, power = 0.0;
    std::vector<double> aliasMass(g.emitterCount, 0.0);
    for (uint32_t i = 0; i < g.emitterCount; ++i) {
        const gpu::Emitter& e = t.emitters[g.firstEmitter + i];
        triangles.push_back(e.triangle);
        pmfSum += e.pmf;
        power += emitterPower(scene, e.triangle);
        EXPECT_LT(e.alias, g.emitterCount);
        aliasMass[i] += e.aliasThreshold / g.emitterCount;
        aliasMass[std::min(e.alias, g.emitterCount - 1)] +=
            (1.0 - e.aliasThreshold) / g.emitterCount;
    }
    EXPECT_NEAR(pmfSum, 1.0, 1e-5);
    EXPECT_NEAR(g.power, power, 1e-5 * power);
    for (uint32_t i = 0; i < g.emitterCount; ++i)
        EXPECT_NEAR(aliasMass[i], t.emitters[g.firstEmitter + i].pmf, 1e-5);
    return triangles;
}

// Checks the tables' invariants: every emitter in exactly one light, each light's alias table,
// the per-triangle index agreeing, and the group of all emitters (the shared light component)
// holding every emitter once, with the scene's total power, after the lights' tables.
void expectConsistent(const Scene& scene, const LightGroupTable& t) {
    ASSERT_EQ(t.triangleLight.size(), scene.triangles.size());
    std::vector<uint32_t> emitters;
    for (uint32_t tri = 0; tri < scene.triangles.size(); ++tri)
        if (emitterPower(scene, tri) > 0.0f) emitters.push_back(tri);
    size_t inLights = 0;
    for (uint32_t l = 0; l < t.lights.size(); ++l) {
        for (uint32_t tri : expectAliasTable(scene, t, t.lights[l])) {
            EXPECT_EQ(t.triangleLight[tri], l);
            ++inLights;
        }
    }
    EXPECT_EQ(inLights, emitters.size());
    std::vector<uint32_t> all = expectAliasTable(scene, t, t.allEmitters);
    std::sort(all.begin(), all.end());
    EXPECT_EQ(all, emitters);
    EXPECT_EQ(t.allEmitters.firstEmitter, inLights);
    EXPECT_EQ(t.emitters.size(), 2 * emitters.size());
    // The group of all emitters is light sampling's table itself, entry for entry.
    const EmitterTable table = buildEmitters(scene);
    EXPECT_EQ(t.allEmitters.power, table.totalPower);
    for (size_t i = 0; i < table.emitters.size(); ++i) {
        const gpu::Emitter& a = table.emitters[i];
        const gpu::Emitter& b = t.emitters[t.allEmitters.firstEmitter + i];
        EXPECT_EQ(a.triangle, b.triangle);
        EXPECT_EQ(a.aliasThreshold, b.aliasThreshold);
        EXPECT_EQ(a.alias, b.alias);
        EXPECT_EQ(a.pmf, b.pmf);
    }
    const std::vector<gpu::LightGroup> device = t.deviceGroups();
    ASSERT_EQ(device.size(), t.lights.size() + 1);
    EXPECT_EQ(device.back().firstEmitter, t.allEmitters.firstEmitter);
}

TEST(LightGroups, TrianglesSharingAPositionFormOneLight) {
    Scene s;
    s.path = "groups.gltf";
    s.materials = {testMaterial(glm::vec3(0.0f)), testMaterial(glm::vec3(1.0f)), testMaterial(glm::vec3(3.0f))};
    addTriangle(s, {-5, 0, -5}, {5, 0, -5}, {-5, 0, 5}, 0);  // floor, not a light
    // Light A: a quad of two triangles sharing an edge (by position only), plus a triangle
    // touching the quad at one corner.
    addTriangle(s, {0, 2, 0}, {1, 2, 0}, {1, 2, 1}, 1);
    addTriangle(s, {0, 2, 0}, {1, 2, 1}, {0, 2, 1}, 1);
    addTriangle(s, {1, 2, 1}, {2, 2, 1}, {2, 2, 2}, 2);
    // Light B: a separate quad.
    addTriangle(s, {3, 2, 0}, {4, 2, 0}, {4, 2, 1}, 2);
    addTriangle(s, {3, 2, 0}, {4, 2, 1}, {3, 2, 1}, 2);
    // Light C: a lone triangle.
    addTriangle(s, {-3, 1, 0}, {-3, 1, 1}, {-3, 3, 0.5f}, 1);
    s.cameras.push_back(Camera{});
    finalizeScene(s);

    const LightGroupTable t = buildLightGroups(s);
    ASSERT_EQ(t.lights.size(), 3u);
    EXPECT_EQ(t.triangleLight[0], gpu::LIGHT_NONE);
    EXPECT_EQ(t.triangleLight[1], 0u);
    EXPECT_EQ(t.triangleLight[2], 0u);
    EXPECT_EQ(t.triangleLight[3], 0u);
    EXPECT_EQ(t.triangleLight[4], 1u);
    EXPECT_EQ(t.triangleLight[5], 1u);
    EXPECT_EQ(t.triangleLight[6], 2u);
    EXPECT_EQ(t.lights[0].emitterCount, 3u);
    // Within light A the brighter triangle (same area, 3x the radiance) gets 3/5 of the pmf.
    EXPECT_NEAR(t.emitters[t.lights[0].firstEmitter + 2].pmf, 0.6, 1e-6);
    expectConsistent(s, t);
}

TEST(LightGroups, ShippedScenes) {
    struct Case {
        const char* file;
        size_t lights;
    };
    for (const Case& c : {Case{"scenes/checkers-two-lights.glb", 2}, Case{"scenes/cornell-classic.glb", 1},
                          Case{"scenes/cornell-glass.glb", 1}, Case{"scenes/cornell-spheres.glb", 1}}) {
        const Scene scene = loadScene(test::sourcePath(c.file));
        const LightGroupTable t = buildLightGroups(scene);
        EXPECT_EQ(t.lights.size(), c.lights) << c.file;
        expectConsistent(scene, t);
    }
}

}  // namespace
}  // namespace pmcr
