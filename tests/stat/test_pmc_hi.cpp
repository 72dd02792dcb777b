// PMC-HI (pmc-hi, and pmc-ip-hi with and without feedback) is unbiased: its mean image equals MIS direct lighting's pixel by pixel, with
// one light component per light, with one shared by all, and where delta BSDFs (glass, mirror)
// are sampled by the BSDF component alone, and on a scene lit by an area light, a point light and
// an environment image together (the environment one more component, the point light a
// next-event estimate beside the mixture); the furnace gives its analytic answer; a seed gives
// the same image bit for bit. The shader tests (tests/gpu/test_pmc_hi.cpp) check the mixture.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <string>

#include "core/error.h"
#include "gpu_test.h"
#include "render_test.h"
#include "scene_builder.h"
#include "statistics.h"

namespace pmcr::test {
namespace {

class PmcHiTest : public GpuTest {};

RenderSettings pmcHiSettings(int size, uint32_t spp) {
    RenderSettings s;
    s.method = "pmc-hi";
    s.width = size;
    s.height = size;
    s.spp = spp;
    s.maxDepth = 1;
    return s;
}

TEST_F(PmcHiTest, SameSeedSameImageBitForBit) {
    const Scene& scene = testScene("scenes/checkers-two-lights.glb");
    RenderSettings s = pmcHiSettings(16, 2);
    auto a = renderForTest(scene, s);
    auto b = renderForTest(scene, s);
    EXPECT_EQ(a.output.image.rgb, b.output.image.rgb);
    EXPECT_EQ(a.output.cameraSamples, 16u * 16u * 2u);
    const auto& stats = a.stats["method_stats"];
    EXPECT_EQ(stats["lights"].get<int>(), 2);
    EXPECT_EQ(stats["light_components"].get<int>(), 2);
    EXPECT_EQ(stats["population"].get<int>(), 8);  // 2 x (BSDF, two lights, cone)
    EXPECT_EQ(stats["samples_per_estimate"].get<int>(), 16);
    // The figure 7 maps: one per light, BSDF and cone; the weights sum to 1 where estimated.
    ASSERT_EQ(a.output.diagnostics.size(), 4u);
    EXPECT_EQ(a.output.diagnostics[0].first, "alpha-brdf");
    EXPECT_EQ(a.output.diagnostics[1].first, "alpha-light0");
    EXPECT_EQ(a.output.diagnostics[2].first, "alpha-light1");
    EXPECT_EQ(a.output.diagnostics[3].first, "alpha-cone");
    int estimated = 0;
    for (size_t p = 0; p < a.output.image.pixelCount(); ++p) {
        double sum = 0.0;
        for (const auto& d : a.output.diagnostics)
            sum += d.second.rgb[3 * p];
        if (sum > 0.0) {
            ++estimated;
            EXPECT_NEAR(sum, 1.0, 1e-4) << "pixel " << p;
        }
    }
    EXPECT_GT(estimated, 0);
}

TEST_F(PmcHiTest, FurnaceGivesItsAnalyticValue) {
    const MeanEstimate e = meanOverRenders(testScene("scenes/furnace.glb"), pmcHiSettings(16, 4), 4, 11);
    // Emission seen directly plus one bounce of a Kd 0.5 surface: 1 - 0.5^2.
    EXPECT_NEAR(e.mean, 0.75, 5.0 * e.standardError + 2e-3) << "standard error " << e.standardError;
}

// Independent MIS direct-lighting renders of a scene at a size, rendered once per test binary.
const ImageMoments& baseline(const std::string& scenePath, const RenderSettings& like) {
    static std::map<std::string, ImageMoments> cache;
    const std::string key = scenePath + "@" + std::to_string(like.width);
    auto it = cache.find(key);
    if (it != cache.end()) return it->second;
    RenderSettings base = like;
    base.method = "direct";
    base.options = {{"light-samples", "4"}};
    base.spp = 32;
    return cache.emplace(key, renderMoments(testScene(scenePath), base, 8, 8000)).first->second;
}

// The mean of independent PMC-HI renders against independent MIS direct-lighting renders, per
// pixel (Sidak-corrected z-test, at least 99.75% of pixels pass).
PixelTestResult zTest(const std::string& scenePath, const RenderSettings& method, int renders) {
    return zTestRenders(testScene(scenePath), method, renders, 3000, baseline(scenePath, method));
}

void expectUnbiased(const std::string& scenePath, const RenderSettings& method, int renders) {
    const auto result = zTest(scenePath, method, renders);
    EXPECT_GE(result.passFraction, 0.9975) << result.describe();
}

TEST_F(PmcHiTest, UnbiasedWithOneComponentPerLight) {
    expectUnbiased("scenes/checkers-two-lights.glb", pmcHiSettings(24, 4), 32);
}

TEST_F(PmcHiTest, UnbiasedWithOneSharedLightComponent) {
    RenderSettings s = pmcHiSettings(24, 4);
    s.options["max-light-components"] = "1";
    s.options["iterations"] = "3";
    expectUnbiased("scenes/checkers-two-lights.glb", s, 32);
}

// A first iteration smaller than the others (--initial-population-per-component): the estimate
// averages all the iterations' weighted samples, so each iteration counts in proportion to its
// population, and stays unbiased.
TEST_F(PmcHiTest, UnbiasedWithASmallerFirstIteration) {
    RenderSettings s = pmcHiSettings(24, 4);
    s.options["initial-population-per-component"] = "1";
    s.options["population-per-component"] = "3";
    const auto run = renderForTest(testScene("scenes/checkers-two-lights.glb"), s);
    EXPECT_EQ(run.stats["method_stats"]["samples_per_estimate"].get<int>(), 16);  // (1 + 3) x 4
    expectUnbiased("scenes/checkers-two-lights.glb", s, 32);
}

// Given first-iteration weights (--initial-alpha), here all on the BSDF: the lights keep the
// defensive floor's weight, the deterministic mixture gives them a sample in some estimates and
// none in others, and the estimate (eq. 1 with K's weights) stays unbiased.
TEST_F(PmcHiTest, UnbiasedWithGivenInitialWeights) {
    RenderSettings s = pmcHiSettings(24, 4);
    s.options["initial-alpha"] = "1/0/0";
    s.options["iterations"] = "1";
    s.options["population-per-component"] = "3";
    expectUnbiased("scenes/checkers-two-lights.glb", s, 32);
}

// Weights moved only part of the way to eq. 9's (--adapt-rate) still depend on earlier
// iterations only, so the estimate stays unbiased.
TEST_F(PmcHiTest, UnbiasedWithPartialUpdates) {
    RenderSettings s = pmcHiSettings(24, 4);
    s.options["adapt-rate"] = "0.5";
    s.options["iterations"] = "3";
    expectUnbiased("scenes/plant-shadows.glb", s, 32);
}

TEST_F(PmcHiTest, BadWeightOptionsAreErrors) {
    RenderSettings s = pmcHiSettings(8, 1);
    s.options["initial-alpha"] = "0.5/0.5";  // checkers-two-lights has the BSDF and two lights
    EXPECT_THROW(renderForTest(testScene("scenes/checkers-two-lights.glb"), s), Error);
    s.options["max-light-components"] = "1";  // one shared light component: two weights
    EXPECT_NO_THROW(renderForTest(testScene("scenes/checkers-two-lights.glb"), s));
    s.options["initial-alpha"] = "0.5/-1";
    EXPECT_THROW(renderForTest(testScene("scenes/checkers-two-lights.glb"), s), Error);
    s.options["initial-alpha"] = "paper";
    s.options["adapt-rate"] = "0";
    EXPECT_THROW(renderForTest(testScene("scenes/checkers-two-lights.glb"), s), Error);
}

// The per-component variant (sec. 7: w = f / h_k of the sample's own component) estimates
// sum_k alpha_k int_{supp h_k} f: a light component sees only its light, the cone only the
// cone, so with two lights it is biased low, and the z-test sees it (which also shows the test
// has the power to see such a bias).
TEST_F(PmcHiTest, PerComponentVariantIsBiased) {
    RenderSettings s = pmcHiSettings(24, 4);
    s.options["rao-blackwell"] = "off";
    const auto result = zTest("scenes/checkers-two-lights.glb", s, 32);
    EXPECT_LT(result.passFraction, 0.9975) << result.describe();
}

// plant-shadows' two lights differ in power (radiance 120 and 25, equal areas): the first
// iteration's light weights are then unequal (in proportion to power), and the estimate must
// stay unbiased with them, with the per-component sample streams and three iterations.
TEST_F(PmcHiTest, UnbiasedWithLightsOfUnequalPower) {
    RenderSettings s = pmcHiSettings(24, 4);
    s.options["iterations"] = "3";
    expectUnbiased("scenes/plant-shadows.glb", s, 32);
}

TEST_F(PmcHiTest, UnbiasedWithDeltaBsdfs) {
    expectUnbiased("scenes/cornell-glass.glb", pmcHiSettings(24, 4), 32);
}

// pmc-ip-hi: PMC-IP over PMC-HI, each pixel's PMC-HI weights seeded from its previous
// image-plane iteration (sec. 6.1), and without that feedback.
RenderSettings pmcIpHiSettings(int size, uint32_t spp, bool feedback) {
    RenderSettings s = pmcHiSettings(size, spp);
    s.method = "pmc-ip-hi";
    s.options["initial-spp"] = "2";
    s.options["spp-per-iteration"] = "1";
    s.options["feedback"] = feedback ? "on" : "off";
    return s;
}

TEST_F(PmcHiTest, FeedbackSameSeedSameImageAndAlphaMaps) {
    const Scene& scene = testScene("scenes/checkers-two-lights.glb");
    RenderSettings s = pmcIpHiSettings(16, 4, true);
    auto a = renderForTest(scene, s);
    auto b = renderForTest(scene, s);
    EXPECT_EQ(a.output.image.rgb, b.output.image.rgb);
    EXPECT_EQ(a.stats["method_stats"]["iterations_completed"].get<int>(), 3);
    EXPECT_TRUE(a.stats["method_stats"]["feedback"].get<bool>());
    // PMC-IP's alpha, samples and variance, then the PMC-HI maps.
    ASSERT_EQ(a.output.diagnostics.size(), 7u);
    EXPECT_EQ(a.output.diagnostics[3].first, "alpha-brdf");
    EXPECT_EQ(a.output.diagnostics[6].first, "alpha-cone");
}

TEST_F(PmcHiTest, UnbiasedWithFeedback) {
    expectUnbiased("scenes/checkers-two-lights.glb", pmcIpHiSettings(24, 4, true), 32);
}

TEST_F(PmcHiTest, UnbiasedWithoutFeedback) {
    expectUnbiased("scenes/checkers-two-lights.glb", pmcIpHiSettings(24, 4, false), 32);
}

// Every kind of light at once: a glossy floor (y = 0) with a diffuse blocker above it that
// shadows part of it, an area light facing down, a point light and a random environment image
// with a sun, seen at an angle so that the top rows see the sky past the floor's edge.
Scene allLightsScene() {
    Scene s;
    s.path = "pmc-hi-all-lights.gltf";
    s.materials = {testMaterial(glm::vec3(0.0f), false, 0.3f), testMaterial(glm::vec3(0.0f)),
                   testMaterial(glm::vec3(6.0f, 5.0f, 4.0f))};
    // Quad (x0..x1, z0..z1) at height y facing up (+y) or down.
    auto quad = [&](float x0, float x1, float z0, float z1, float y, bool up, uint32_t material) {
        if (up) {
            addTriangle(s, {x0, y, z0}, {x0, y, z1}, {x1, y, z1}, material);
            addTriangle(s, {x0, y, z0}, {x1, y, z1}, {x1, y, z0}, material);
        } else {
            addTriangle(s, {x0, y, z0}, {x1, y, z1}, {x0, y, z1}, material);
            addTriangle(s, {x0, y, z0}, {x1, y, z0}, {x1, y, z1}, material);
        }
    };
    quad(-4, 4, -4, 4, 0.0f, true, 0);
    quad(-0.6f, 0.2f, -0.4f, 0.4f, 0.8f, true, 1);
    quad(-1.5f, -0.5f, -0.5f, 0.5f, 2.5f, false, 2);
    gpu::PunctualLight point{};
    point.type = gpu::PUNCTUAL_POINT;
    point.position = glm::vec3(1.2f, 1.5f, 0.3f);
    point.direction = glm::vec3(0, -1, 0);
    point.intensity = glm::vec3(3.0f, 3.0f, 2.5f);
    s.punctualLights = {point};
    std::mt19937 rng(23);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    s.environment.source = "random-sky.exr";
    s.environment.kind = gpu::ENV_IMAGE;
    s.environment.image = Image(16, 8);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x)
            s.environment.image.set(x, y, glm::vec3(0.3f * u(rng), 0.4f * u(rng), 0.6f * u(rng)));
    s.environment.image.set(9, 2, glm::vec3(12.0f, 11.0f, 9.0f));  // a sun
    s.environment.rotation = 0.4f;
    Camera camera;
    camera.position = glm::vec3(0.0f, 3.0f, 4.5f);
    camera.forward = glm::normalize(glm::vec3(0.0f, -3.0f, -4.5f));
    camera.right = glm::vec3(1, 0, 0);
    camera.up = glm::cross(camera.right, camera.forward);
    camera.yfov = 0.9f;
    s.cameras.push_back(camera);
    finalizeScene(s);
    return s;
}

// Independent MIS direct-lighting renders of allLightsScene, rendered once per test binary.
const ImageMoments& allLightsBaseline(const Scene& scene) {
    static const ImageMoments moments = [&] {
        RenderSettings base = pmcHiSettings(24, 32);
        base.method = "direct";
        base.options = {{"light-samples", "4"}};
        return renderMoments(scene, base, 8, 8000);
    }();
    return moments;
}

TEST_F(PmcHiTest, UnbiasedWithAreaPointAndEnvironmentLights) {
    const Scene scene = allLightsScene();
    const RenderSettings s = pmcHiSettings(24, 4);
    const auto run = renderForTest(scene, s);
    const auto& stats = run.stats["method_stats"];
    EXPECT_EQ(stats["light_components"].get<int>(), 1);
    EXPECT_TRUE(stats["environment_component"].get<bool>());
    EXPECT_EQ(stats["punctual_lights"].get<int>(), 1);
    EXPECT_EQ(stats["population"].get<int>(), 8);  // 2 x (BSDF, light, environment, cone)
    ASSERT_EQ(run.output.diagnostics.size(), 4u);
    EXPECT_EQ(run.output.diagnostics[2].first, "alpha-env");
    const auto result = zTestRenders(scene, s, 32, 3000, allLightsBaseline(scene));
    EXPECT_GE(result.passFraction, 0.9975) << result.describe();
}

TEST_F(PmcHiTest, FeedbackUnbiasedWithAreaPointAndEnvironmentLights) {
    const Scene scene = allLightsScene();
    const auto result = zTestRenders(scene, pmcIpHiSettings(24, 4, true), 32, 3100, allLightsBaseline(scene));
    EXPECT_GE(result.passFraction, 0.9975) << result.describe();
}

}  // namespace
}  // namespace pmcr::test
