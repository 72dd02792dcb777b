// shaders/common/environment.glsl: envSample draws each pixel of an environment image with the
// host's alias-table probability (chi-square), returns the density envPdf gives its direction
// and the radiance envRadiance sees there, and envPdf integrates to one over the sphere; for a
// constant environment too. The image is random with black pixels and rotated, so that a
// mismatch between the sampled and the evaluated direction (the rotation, the mapping) shows.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "distribution_test.h"
#include "gpu_test.h"
#include "render/gpu_scene.h"
#include "scene/environment.h"
#include "scene/scene.h"
#include "scene_builder.h"

namespace pmcr::test {
namespace {

struct EnvironmentPush {
    uint32_t mode;
    uint32_t count;
    uint32_t seed;
};

// A random W x H environment image: a quarter of its pixels black, one bright pixel.
Environment randomEnvironment(int w, int h, float rotationDegrees, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Environment env;
    env.source = "random-environment.exr";
    env.kind = gpu::ENV_IMAGE;
    env.image = Image(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            env.image.set(x, y, u(rng) < 0.25f ? glm::vec3(0.0f) : glm::vec3(u(rng), u(rng), u(rng)));
    env.image.set(w / 3, h / 4, glm::vec3(40.0f, 30.0f, 20.0f));
    env.scale = 1.5f;
    env.rotation = glm::radians(rotationDegrees);
    return env;
}

// One triangle that does not emit, lit by `env`.
Scene environmentScene(Environment env) {
    Scene s;
    s.path = "environment-test.gltf";
    s.materials = {testMaterial(glm::vec3(0.0f))};
    addTriangle(s, {-1, 0, -1}, {1, 0, -1}, {0, 0, 1}, 0);
    s.cameras.push_back(Camera{});
    s.environment = std::move(env);
    finalizeScene(s);
    return s;
}

// The image pixel direction d falls in, as envPixel computes it.
size_t hostPixel(const Environment& env, const glm::vec3& d) {
    const float c = std::cos(env.rotation), s = std::sin(env.rotation);
    const glm::vec3 l(c * d.x + s * d.z, d.y, -s * d.x + c * d.z);
    const double u = 0.5 + std::atan2(double(l.x), double(-l.z)) / (2.0 * std::numbers::pi);
    const double v = std::acos(std::clamp(double(l.y), -1.0, 1.0)) / std::numbers::pi;
    const int w = env.image.width, h = env.image.height;
    const int x = std::min(int(u * w), w - 1), y = std::min(int(v * h), h - 1);
    return size_t(y) * size_t(w) + size_t(x);
}

class EnvironmentTest : public GpuTest {
protected:
    std::vector<glm::vec4> call(const GpuScene& scene, uint32_t mode, uint32_t n, uint32_t values) {
        auto out = zeros(size_t(n) * values * 16, "environment results");
        run("tests/environment_test", EnvironmentPush{mode, n, 11}, n, {&out}, &scene.descriptorSet());
        return out.download<glm::vec4>(size_t(n) * values);
    }
};

TEST_F(EnvironmentTest, ImageSamplesFollowThePixelTable) {
    const Scene scene = environmentScene(randomEnvironment(24, 12, 40.0f, 3));
    const Environment& env = scene.environment;
    const GpuScene gpuScene(context(), layout(), scene, 0, 8, 8);
    const uint32_t n = 400000;
    const auto r = call(gpuScene, 0, n, 3);
    const auto table = environmentAliasTable(env);
    std::vector<double> observed(table.size(), 0.0), expected(table.size(), 0.0);
    for (size_t i = 0; i < table.size(); ++i) expected[i] = double(table[i].pmf) * n;
    uint32_t pdfMismatch = 0, radianceMismatch = 0;
    for (uint32_t i = 0; i < n; ++i) {
        const glm::vec3 wi(r[3 * i]);
        const float pdf = r[3 * i].w;
        ASSERT_NEAR(glm::length(wi), 1.0f, 1e-4f) << "sample " << i;
        ASSERT_TRUE(pdf > 0.0f && std::isfinite(pdf)) << "sample " << i << " pdf " << pdf;
        observed[hostPixel(env, wi)] += 1.0;
        // A direction on a pixel's edge may round into its neighbour when mapped back.
        pdfMismatch += std::abs(r[3 * i + 1].w - pdf) > 1e-3f * pdf;
        radianceMismatch += glm::vec3(r[3 * i + 1]) != glm::vec3(r[3 * i + 2]);
    }
    EXPECT_LE(pdfMismatch, n / 1000) << "envSample's pdf differs from envPdf of its direction";
    EXPECT_LE(radianceMismatch, n / 1000) << "envSample's Le differs from envRadiance of its direction";
    EXPECT_TRUE(chi2Passes(observed, expected, "environment image pixels"));
}

// E[envPdf(d)] over uniform directions d is 1 / (4 pi) when envPdf is a density.
TEST_F(EnvironmentTest, PdfIntegratesToOne) {
    for (const bool image : {true, false}) {
        SCOPED_TRACE(image ? "image" : "constant");
        Environment env = randomEnvironment(32, 16, -75.0f, 5);
        if (!image) env = loadEnvironment({"0.2,0.3,0.4"});
        const Scene scene = environmentScene(std::move(env));
        const GpuScene gpuScene(context(), layout(), scene, 0, 8, 8);
        const uint32_t n = 400000;
        const auto r = call(gpuScene, 1, n, 1);
        double sum = 0.0, sumSq = 0.0;
        for (uint32_t i = 0; i < n; ++i) {
            const double v = 4.0 * std::numbers::pi * r[i].w;
            sum += v;
            sumSq += v * v;
        }
        const double mean = sum / n;
        const double stderr = std::sqrt(std::max(0.0, sumSq / n - mean * mean) / n);
        EXPECT_NEAR(mean, 1.0, 5.0 * stderr + 1e-4) << "standard error " << stderr;
    }
}

}  // namespace
}  // namespace pmcr::test
