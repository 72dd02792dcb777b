// PSSMLT over the path tracer (--over pt) is unbiased: with b estimated from an independent bootstrap and the chains started in
// proportion to the bootstrap weights, the mean image over independent renders equals path
// tracing's, pixel by pixel; the furnace gives its analytic answer; every mutation deposits one
// e_d in all; a seed gives the same image bit for bit; and every scene renders without NaN.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include "gpu_test.h"
#include "render_test.h"
#include "statistics.h"

namespace pmcr::test {
namespace {

class PssmltTest : public GpuTest {};

// Over the path tracer (--over pt); test_pssmlt_bdpt.cpp tests the default, over bdpt.
RenderSettings pssmltSettings(int size, uint32_t spp) {
    RenderSettings s;
    s.method = "pssmlt";
    s.options["over"] = "pt";
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

// Passes run together (--passes-per-batch, a GPU's default; issue 38) give the image of passes
// run one by one, bit for bit: the chains carry their random numbers from submission to
// submission and the splat film sums integer quanta. 7 passes 3 at a time: 3, 3, then 1.
TEST_F(PssmltTest, PassesRunTogetherSameImage) {
    RenderSettings s = pssmltSettings(32, 7);
    s.options["chains"] = "256";  // 4 steps per chain per pass, split over dispatches
    s.options["steps-per-dispatch"] = "3";
    const auto [one, three] = expectPassesPerBatchKeepTheImage(testScene("scenes/cornell-glass.glb"), s, 3);
    EXPECT_EQ(three.stats["method_stats"]["mutations"].get<uint64_t>(),
              one.stats["method_stats"]["mutations"].get<uint64_t>());
}

// Every mutation deposits e_d in all (a at the proposal, 1 - a at the current path), each pass
// is about one mutation per pixel, and both kinds of step are proposed and accepted.
TEST_F(PssmltTest, EveryMutationDepositsOneUnit) {
    expectPssmltMutationsDepositOneUnit(pssmltSettings(32, 3), 1e-5);
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

}  // namespace
}  // namespace pmcr::test
