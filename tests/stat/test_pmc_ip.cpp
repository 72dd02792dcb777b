// PMC-IP (pmc-ip over path tracing, pmc-ip-direct over MIS direct lighting) is unbiased: its
// mean image equals the baseline's pixel by pixel, the furnace gives its analytic answer, and a
// seed gives the same image bit for bit. The host tests (test_image_plane_sampler.cpp) check
// the allocation and the estimator itself.
#include <gtest/gtest.h>

#include <cmath>

#include "gpu_test.h"
#include "render_test.h"
#include "statistics.h"

namespace pmcr::test {
namespace {

class PmcIpTest : public GpuTest {};

RenderSettings pmcIpSettings(const std::string& method, int size, uint32_t spp) {
    return renderSettings(method, size, size, spp, 8);
}

TEST_F(PmcIpTest, SameSeedSameImageBitForBit) {
    const Scene& scene = testScene("scenes/cornell-glass.glb");
    RenderSettings s = pmcIpSettings("pmc-ip", 32, 12);
    auto a = renderForTest(scene, s);
    auto b = renderForTest(scene, s);
    EXPECT_EQ(a.output.image.rgb, b.output.image.rgb);
    // The budget, give or take the leave-one-out normalisation (image_plane_sampler.h).
    EXPECT_NEAR(double(a.output.cameraSamples), 32.0 * 32.0 * 12.0, 0.01 * 32.0 * 32.0 * 12.0);
    EXPECT_EQ(a.stats["method_stats"]["iterations_completed"].get<int>(), 3);
    // The diagnostics: alpha map, sample counts, variance.
    ASSERT_EQ(a.output.diagnostics.size(), 3u);
    EXPECT_EQ(a.output.diagnostics[0].first, "alpha");
    double samples = 0.0;
    for (size_t i = 0; i < a.output.diagnostics[1].second.pixelCount(); ++i)
        samples += a.output.diagnostics[1].second.rgb[3 * i];
    EXPECT_EQ(samples, double(a.output.cameraSamples));
}

// The results are added and the requests written on several threads on a GPU (issue 38):
// every pixel's results in request order, so the image is the same bit for bit for any count.
TEST_F(PmcIpTest, HostThreadsSameImageBitForBit) {
    const Scene& scene = testScene("scenes/cornell-glass.glb");
    for (const char* method : {"pmc-ip", "pmc-ip-hi"}) {
        RenderSettings s = pmcIpSettings(method, 128, 12);  // batches of several blocks
        s.options["host-threads"] = "1";
        auto one = renderForTest(scene, s);
        s.options["host-threads"] = "3";
        auto three = renderForTest(scene, s);
        EXPECT_EQ(one.output.image.rgb, three.output.image.rgb) << method;
        EXPECT_EQ(one.output.cameraSamples, three.output.cameraSamples) << method;
        // Each result added once, whichever block takes its pixel's run: the per-pixel counts
        // add up to the samples taken, and to the budget.
        double counted = 0.0;
        const Image& counts = three.output.diagnostics[1].second;
        for (size_t i = 0; i < counts.pixelCount(); ++i) counted += counts.rgb[3 * i];
        EXPECT_EQ(counted, double(three.output.cameraSamples)) << method;
        EXPECT_NEAR(double(three.output.cameraSamples), 128.0 * 128.0 * 12.0, 0.01 * 128.0 * 128.0 * 12.0) << method;
    }
}

TEST_F(PmcIpTest, FurnaceGivesItsAnalyticValue) {
    for (const char* method : {"pmc-ip", "pmc-ip-direct"}) {
        const int depth = 3;
        RenderSettings s = pmcIpSettings(method, 24, 12);
        s.maxDepth = depth;
        const MeanEstimate e = meanOverRenders(testScene("scenes/furnace.glb"), s, 4, 11);
        const double expected = 1.0 - std::pow(0.5, std::string(method) == "pmc-ip" ? depth + 1 : 2);
        EXPECT_NEAR(e.mean, expected, 5.0 * e.standardError + 2e-3)
            << method << ", standard error " << e.standardError;
    }
}

// The mean of independent PMC-IP renders against independent renders of its baseline, per
// pixel (Sidak-corrected z-test, at least 99.75% of pixels pass, as Mitsuba's render tests).
void expectUnbiased(RenderSettings method, const std::string& baseline, int renders, int baselineRenders) {
    const Scene& scene = testScene("scenes/cornell-glass.glb");
    RenderSettings base = method;
    base.method = baseline;
    base.options.clear();
    if (method.options.count("light-samples")) base.options["light-samples"] = method.options["light-samples"];
    base.spp = 64;
    const auto result = zTestRenders(scene, method, renders, 2000, renderMoments(scene, base, baselineRenders, 7000));
    EXPECT_GE(result.passFraction, 0.9975) << result.describe();
}

TEST_F(PmcIpTest, UnbiasedAgainstPathTracing) {
    expectUnbiased(pmcIpSettings("pmc-ip", 20, 24), "pt", 40, 16);
}

// Without pilot samples after the first iteration (pixels may get no sample in an iteration;
// the first iteration's samples alone drive the adaptation).
TEST_F(PmcIpTest, UnbiasedWithoutPilotSamples) {
    RenderSettings s = pmcIpSettings("pmc-ip", 20, 24);
    s.options["min-spp"] = "0";
    expectUnbiased(s, "pt", 40, 16);
}

TEST_F(PmcIpTest, DirectUnbiasedAgainstMisDirectLighting) {
    RenderSettings s = pmcIpSettings("pmc-ip-direct", 20, 24);
    s.options["light-samples"] = "2";
    expectUnbiased(s, "direct", 40, 16);
}

}  // namespace
}  // namespace pmcr::test
