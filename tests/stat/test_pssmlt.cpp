// PSSMLT is unbiased: with b estimated from an independent bootstrap and the chains started in
// proportion to the bootstrap weights, the mean image over independent renders equals path
// tracing's, pixel by pixel; the furnace gives its analytic answer; every mutation deposits one
// e_d in all; a seed gives the same image bit for bit; and every scene renders without NaN.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <set>

#include "gpu_test.h"
#include "render_test.h"
#include "scene/gltf_loader.h"
#include "statistics.h"
#include "test_util.h"

namespace pmcr::test {
namespace {

class PssmltTest : public GpuTest {};

RenderSettings pssmltSettings(int size, uint32_t spp) {
    RenderSettings s;
    s.method = "pssmlt";
    s.width = size;
    s.height = size;
    s.spp = spp;
    s.maxDepth = 8;
    return s;
}

TEST_F(PssmltTest, SameSeedSameImageBitForBit) {
    const Scene& scene = testScene("scenes/cornell-glass.glb");
    RenderSettings s = pssmltSettings(32, 2);
    s.options["chains"] = "256";  // 4 steps per chain per pass, split over dispatches
    s.options["steps-per-dispatch"] = "3";
    auto a = renderForTest(scene, s);
    auto b = renderForTest(scene, s);
    EXPECT_EQ(a.output.image.rgb, b.output.image.rgb);
    s.seed = 2;
    auto c = renderForTest(scene, s);
    EXPECT_NE(a.output.image.rgb, c.output.image.rgb);
}

// Every mutation deposits e_d in all (a at the proposal, 1 - a at the current path), each pass
// is about one mutation per pixel, and both kinds of step are proposed and accepted.
TEST_F(PssmltTest, EveryMutationDepositsOneUnit) {
    RenderSettings s = pssmltSettings(32, 3);
    s.options["chains"] = "100";
    auto r = renderForTest(testScene("scenes/cornell-glass.glb"), s);
    const auto& m = r.stats["method_stats"];
    EXPECT_EQ(m["passes"].get<int>(), 3);
    EXPECT_EQ(m["steps_per_pass"].get<uint32_t>(), 10u);  // round(1024 / 100)
    EXPECT_EQ(m["mutations"].get<uint64_t>(), 3000u);
    EXPECT_EQ(m["bootstrap_samples"].get<uint64_t>(), 4u * 1024u);
    EXPECT_EQ(m["deposits_dropped"].get<uint64_t>(), 0u);
    EXPECT_NEAR(m["energy_not_deposited"].get<double>(), 0.0, 1e-5);
    const double large = m["large_step_proposed"].get<double>();
    const double small = m["small_step_proposed"].get<double>();
    EXPECT_EQ(large + small, 3000.0);
    EXPECT_NEAR(large / 3000.0, 0.3, 0.05);
    EXPECT_GT(m["large_step_acceptance"].get<double>(), 0.0);
    EXPECT_GT(m["small_step_acceptance"].get<double>(), m["large_step_acceptance"].get<double>());
    EXPECT_LT(m["small_step_acceptance"].get<double>(), 1.0);
    // b_hat is the image's total luminance: close to the rendered image's.
    const glm::dvec3 mean = imageMean(r.output.image);
    const double total = (0.2126 * mean.x + 0.7152 * mean.y + 0.0722 * mean.z) * 1024.0;
    EXPECT_NEAR(m["normalization"].get<double>() / total, 1.0, 0.5);
}

TEST_F(PssmltTest, FurnaceGivesItsAnalyticValue) {
    const int depth = 3;
    RenderSettings s = pssmltSettings(24, 2);
    s.maxDepth = depth;
    const MeanEstimate e = meanOverRenders(testScene("scenes/furnace.glb"), s, 6, 7);
    const double expected = 1.0 - std::pow(0.5, depth + 1);
    EXPECT_NEAR(e.mean, expected, 4.0 * e.standardError + 2e-3) << "standard error " << e.standardError;
}

// The mean of independent PSSMLT renders against independent path-traced renders, per pixel
// (Mitsuba-style: Sidak-corrected z-test, at least 99.75% of pixels pass).
void expectUnbiased(const RenderSettings& pssmlt, int renders) {
    const Scene& scene = testScene("scenes/cornell-glass.glb");
    RenderSettings pt = pssmlt;
    pt.method = "pt";
    pt.options.clear();
    pt.spp = 128;
    const auto t0 = std::chrono::steady_clock::now();
    const auto result = zTestRenders(scene, pssmlt, renders, 1000, renderMoments(scene, pt, 16, 5000));
    EXPECT_GE(result.passFraction, 0.9975) << result.describe();
    std::printf("pssmlt z-test: %s (%.1f s)\n", result.describe().c_str(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
}

// The defaults: a chain per pixel, one step per pass, so mostly the bootstrap's resampling (a
// start-up bias, chains started at uniform bootstrap samples, fails 266 of 400 pixels here).
TEST_F(PssmltTest, UnbiasedAgainstPathTracing) { expectUnbiased(pssmltSettings(20, 32), 40); }

// Few long chains (50 chains, 8 steps per pass, 256 in all), rarer large steps and wider small
// ones: mostly the Metropolis steps' stationarity.
TEST_F(PssmltTest, UnbiasedWithLongChains) {
    RenderSettings s = pssmltSettings(20, 32);
    s.options["chains"] = "50";
    s.options["large-step"] = "0.1";
    s.options["sigma"] = "0.05";
    expectUnbiased(s, 40);
}

std::vector<std::string> sceneFiles() {
    std::vector<std::string> files;
    for (const auto& entry : std::filesystem::directory_iterator(sourcePath("scenes"))) {
        const auto ext = entry.path().extension();
        if (ext == ".glb" || ext == ".gltf") files.push_back("scenes/" + entry.path().filename().string());
    }
    std::sort(files.begin(), files.end());
    return files;
}

// Third-party samples without a light of their own are lit by the shipped sky
// (tests/stat/test_scenes_render.cpp).
const std::set<std::string> kLitBySky = {"scenes/MetalRoughSpheresNoTextures.glb"};

class PssmltSceneRenders : public GpuTest, public ::testing::WithParamInterface<std::string> {};

TEST_P(PssmltSceneRenders, RendersWithoutNaNs) {
    Scene litBySky;
    if (kLitBySky.count(GetParam()))
        litBySky = loadScene(sourcePath(GetParam()), {sourcePath("scenes/sky-afternoon.exr").string()});
    const Scene& scene = kLitBySky.count(GetParam()) ? litBySky : testScene(GetParam());
    RenderSettings s;
    s.method = "pssmlt";
    s.spp = 2;
    s.width = 32;
    s.height = 24;
    auto r = renderForTest(scene, s);
    EXPECT_EQ(r.stats["nan_samples_dropped"].get<uint64_t>(), 0u);
    EXPECT_EQ(r.stats["method_stats"]["deposits_dropped"].get<uint64_t>(), 0u);
    double sum = 0.0;
    for (float v : r.output.image.rgb) {
        ASSERT_TRUE(std::isfinite(v));
        sum += v;
    }
    EXPECT_GT(sum, 0.0) << "an all-black image";
}

INSTANTIATE_TEST_SUITE_P(AllScenes, PssmltSceneRenders, ::testing::ValuesIn(sceneFiles()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                             std::string name = std::filesystem::path(info.param).stem().string();
                             for (char& c : name)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return name;
                         });

}  // namespace
}  // namespace pmcr::test
