// shaders/common/lights.glsl on a small scene: emitter power and selection probabilities equal
// the host's, sampleLight picks each emitter with its selection probability (chi-square over the
// alias table's output) and spreads points uniformly over its area, with pdfArea = pmf / area.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "distribution_test.h"
#include "gpu_test.h"
#include "render/gpu_scene.h"
#include "scene/scene.h"
#include "scene_builder.h"

namespace pmcr::test {
namespace {

struct LightsPush {
    uint32_t mode;
    uint32_t count;
    uint32_t seed;
};

// A floor that does not emit and four emitters of different area, orientation and radiance,
// one of them double-sided.
Scene lightsScene() {
    Scene s;
    s.path = "lights-test.gltf";
    s.materials = {testMaterial(glm::vec3(0.0f), false), testMaterial(glm::vec3(1.0f), false),
                   testMaterial(glm::vec3(4.0f, 2.0f, 1.0f), false),
                   testMaterial(glm::vec3(0.5f, 0.5f, 2.0f), true)};
    addTriangle(s, {-5, 0, -5}, {5, 0, -5}, {-5, 0, 5}, 0);
    addTriangle(s, {0, 2, 0}, {1, 2, 0}, {0, 2, 1}, 1);                       // area 0.5
    addTriangle(s, {2, 1, 0}, {4, 1, 0}, {2, 3, 0}, 2);                       // area 2, facing +z
    addTriangle(s, {-3, 1, 0}, {-3, 1, 1}, {-3, 3, 0.5f}, 3);                 // area 1, double-sided
    addTriangle(s, {1, 0.5f, 1}, {1.3f, 0.7f, 1.1f}, {0.9f, 0.9f, 1.4f}, 1);  // small, tilted
    Camera camera;
    camera.position = glm::vec3(0, 2, 10);
    s.cameras.push_back(camera);
    finalizeScene(s);
    return s;
}

class LightsTest : public GpuTest {
protected:
    std::vector<glm::vec4> call(const GpuScene& scene, uint32_t mode, uint32_t n, uint32_t values) {
        auto out = zeros(size_t(n) * values * 16, "lights results");
        run("tests/lights_test", LightsPush{mode, n, 7}, n, {&out}, &scene.descriptorSet());
        return out.download<glm::vec4>(size_t(n) * values);
    }
};

TEST_F(LightsTest, EmitterPowerAndPmfMatchHost) {
    const Scene scene = lightsScene();
    const GpuScene gpuScene(context(), layout(), scene, 0, 8, 8);
    const uint32_t n = uint32_t(scene.triangles.size());
    const auto r = call(gpuScene, 1, n, 1);
    double total = 0.0;
    for (uint32_t t = 0; t < n; ++t)
        total += emitterPower(scene, t);
    EXPECT_NEAR(gpuScene.info().totalEmitterPower, total, 1e-5 * total);
    for (uint32_t t = 0; t < n; ++t) {
        const double power = emitterPower(scene, t);
        const gpu::Triangle& tri = scene.triangles[t];
        const glm::dvec3 p0 = scene.vertices[tri.i0].position, p1 = scene.vertices[tri.i1].position,
                         p2 = scene.vertices[tri.i2].position;
        const double area = 0.5 * glm::length(glm::cross(p1 - p0, p2 - p0));
        EXPECT_NEAR(r[t].x, power, 1e-5 * power + 1e-7) << "emitterPower " << t;
        EXPECT_NEAR(r[t].y, power / total, 1e-5) << "emitterSelectPmf " << t;
        EXPECT_NEAR(r[t].z, power / total / area, 1e-5 * power / total / area + 1e-7)
            << "emitterAreaPdf " << t;
        EXPECT_NEAR(r[t].w, area, 1e-5 * area) << "triangleArea " << t;
    }
    // Power = pi * area * luminance(Le) * sides (the double-sided emitter, triangle 3, counts
    // twice).
    EXPECT_NEAR(emitterPower(scene, 3),
                std::numbers::pi * 1.0 * luminance(glm::vec3(0.5f, 0.5f, 2.0f)) * 2, 1e-5);
}

TEST_F(LightsTest, SampleLightFollowsPmfAndIsUniformOverArea) {
    const Scene scene = lightsScene();
    const GpuScene gpuScene(context(), layout(), scene, 0, 8, 8);
    const uint32_t triangles = uint32_t(scene.triangles.size());
    const auto info = call(gpuScene, 1, triangles, 1);
    const uint32_t n = 1 << 20;
    const auto r = call(gpuScene, 0, n, 2);

    const int cells = 8;
    std::vector<double> perTriangle(triangles, 0.0);
    std::vector<std::vector<double>> bary(triangles, std::vector<double>(cells * cells, 0.0));
    for (uint32_t i = 0; i < n; ++i) {
        const glm::vec4 a = r[2 * i], b = r[2 * i + 1];
        const uint32_t t = uint32_t(a.w);
        ASSERT_LT(t, triangles);
        perTriangle[t] += 1.0;
        ASSERT_NEAR(b.w, info[t].z, 1e-6f * info[t].z) << "pdfArea = emitterAreaPdf";
        // Barycentrics of the point in its triangle (normal equations of p - p0 = b1 e1 + b2 e2).
        const gpu::Triangle& tri = scene.triangles[t];
        const glm::dvec3 p0 = scene.vertices[tri.i0].position;
        const glm::dvec3 e1 = glm::dvec3(scene.vertices[tri.i1].position) - p0;
        const glm::dvec3 e2 = glm::dvec3(scene.vertices[tri.i2].position) - p0;
        const glm::dvec3 d = glm::dvec3(glm::vec3(a)) - p0;
        const glm::dvec3 normal = glm::normalize(glm::cross(e1, e2));
        ASSERT_NEAR(glm::dot(d, normal), 0.0, 1e-5) << "point off its triangle's plane";
        ASSERT_NEAR(glm::length(glm::dvec3(glm::vec3(b)) - normal), 0.0, 1e-5) << "normal";
        const double a11 = glm::dot(e1, e1), a12 = glm::dot(e1, e2), a22 = glm::dot(e2, e2);
        const double r1 = glm::dot(d, e1), r2 = glm::dot(d, e2), det = a11 * a22 - a12 * a12;
        const double b1 = (a22 * r1 - a12 * r2) / det, b2 = (a11 * r2 - a12 * r1) / det;
        ASSERT_TRUE(b1 >= -1e-5 && b2 >= -1e-5 && b1 + b2 <= 1 + 1e-5) << "outside its triangle";
        bary[t][barycentricCell(b1, b2, cells)] += 1.0;
    }
    std::vector<double> expected(triangles);
    for (uint32_t t = 0; t < triangles; ++t)
        expected[t] = n * double(info[t].y);
    EXPECT_TRUE(chi2Passes(perTriangle, expected, "sampleLight emitter choice"));
    const std::vector<double> share = barycentricCellAreas(cells);
    for (uint32_t t = 0; t < triangles; ++t) {
        if (perTriangle[t] == 0.0)
            continue;
        std::vector<double> e(share);
        for (double& v : e)
            v *= perTriangle[t];
        EXPECT_TRUE(chi2Passes(bary[t], e, "sampleLight points on triangle " + std::to_string(t)));
    }
}

}  // namespace
}  // namespace pmcr::test
