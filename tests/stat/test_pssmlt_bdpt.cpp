// PSSMLT over bidirectional path tracing (--over bdpt, the default): a seed gives the same image
// bit for bit, passes run together give the same image; every mutation deposits one e_d in all,
// spread over the splat lists of the two states; the furnace gives its analytic answer; and the
// mean image equals path tracing's pixel by pixel (per-pixel z-tests, Mitsuba style) on
// cornell-glass, and in the full tier with punctual lights, under a sky with a sun, on
// lamp-room and glass-caustic-torus. Path tracing's references take 1024 samples a pixel, as
// bdpt's tests' (test_bdpt.cpp: with fewer it misses the caustic paths bdpt finds).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "gpu_test.h"
#include "render_test.h"
#include "statistics.h"

namespace pmcr::test {
namespace {

class PssmltOverBdpt : public GpuTest {};
class PssmltOverBdptScenes : public GpuTest {};

RenderSettings overBdpt(int size, uint32_t spp, uint32_t maxDepth = 8) {
    return renderSettings("pssmlt", size, size, spp, maxDepth);
}

ImageMoments ptReference(const Scene& scene, int size, uint32_t maxDepth, int renders, uint32_t spp = 1024) {
    return renderMoments(scene, renderSettings("pt", size, size, spp, maxDepth), renders, 5000);
}

void expectUnbiased(const Scene& scene, const RenderSettings& s, int renders, const ImageMoments& reference) {
    const auto t0 = std::chrono::steady_clock::now();
    const PixelTestResult r = zTestRenders(scene, s, renders, 1000, reference);
    EXPECT_GE(r.passFraction, 0.9975) << r.describe();
    std::printf("  pssmlt over bdpt z-test: %s (%.1f s)\n", r.describe().c_str(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
}

TEST_F(PssmltOverBdpt, SameSeedSameImageBitForBit) {
    const Scene& scene = testScene("scenes/cornell-glass.glb");
    RenderSettings s = overBdpt(24, 2);
    s.options["chains"] = "144";  // 4 steps per chain per pass, split over submissions
    s.options["steps-per-dispatch"] = "3";
    const auto a = renderForTest(scene, s);
    const auto b = renderForTest(scene, s);
    EXPECT_EQ(a.output.image.rgb, b.output.image.rgb);
    EXPECT_EQ(a.stats["method_stats"]["over"].get<std::string>(), "bdpt");
    RenderSettings other = s;
    other.seed = 2;
    EXPECT_NE(a.output.image.rgb, renderForTest(scene, other).output.image.rgb);
    // Passes run together (a GPU's default) give the same bits.
    s.spp = 5;
    expectPassesPerBatchKeepTheImage(scene, s, 3);
}

// Every mutation deposits e_d in all, a over the proposal's splats and 1 - a over the current
// state's, each splat its share of F; both kinds of step are proposed and accepted; b_hat, from
// a bootstrap of bdpt samples, is the image's total luminance.
TEST_F(PssmltOverBdpt, EveryMutationDepositsOneUnit) {
    expectPssmltMutationsDepositOneUnit(overBdpt(32, 3), 1e-4);
}

// Inside the furnace (a Lambertian sphere of albedo 0.5 emitting 0.5) every pixel is
// 1 - 0.5^(D+1) with at most D bounces.
TEST_F(PssmltOverBdpt, FurnaceGivesItsAnalyticValue) {
    const int depth = 3;
    const MeanEstimate e = meanOverRenders(testScene("scenes/furnace.glb"), overBdpt(24, 2, depth), 6, 7);
    const double expected = 1.0 - std::pow(0.5, depth + 1);
    EXPECT_NEAR(e.mean, expected, 4.0 * e.standardError + 2e-3) << "standard error " << e.standardError;
}

TEST_F(PssmltOverBdpt, UnbiasedOnCornellGlass) {
    const Scene& scene = testScene("scenes/cornell-glass.glb");
    expectUnbiased(scene, overBdpt(20, 16), 24, ptReference(scene, 20, 8, 16));
}

// The scenes below have pixels lit by rare paths (a spot's cone edge seen in a corner, a sun
// caustic, the torus's caustic): a render of few passes gives such a pixel nothing or a lot, so
// the mean over renders is skewed and its spread underestimated. With 16 renders of 16 passes at
// 20x20, both --over bdpt and --over pt fail 4 to 12 pixels there, all darker than pt; 4 renders
// of 1024 passes (spot lights, over bdpt) agree there, at twice these tests' cost. These tests
// therefore take large steps only (--large-step 1: an independence sampler, whose proposals are
// plain bdpt samples at random pixels), which still checks the estimator of every light kind,
// the splat lists and the deposits; the small steps are checked on cornell-glass (check tier)
// and lamp-room.
RenderSettings largeStepsOnly(RenderSettings s) {
    s.options["large-step"] = "1";
    return s;
}

TEST_F(PssmltOverBdptScenes, PointAndSpotLights) {
    const Scene scene = withPointAndSpotLights("scenes/cornell-classic.glb");
    expectUnbiased(scene, largeStepsOnly(overBdpt(20, 8)), 40, ptReference(scene, 20, 8, 16));
}

TEST_F(PssmltOverBdptScenes, EnvironmentAndDirectionalLight) {
    const Scene scene = cornellGlassUnderSkyAndSun();
    expectUnbiased(scene, largeStepsOnly(overBdpt(20, 8)), 40, ptReference(scene, 20, 8, 16));
}

TEST_F(PssmltOverBdptScenes, LampRoom) {
    const Scene& scene = testScene("scenes/lamp-room.glb");
    expectUnbiased(scene, overBdpt(20, 16), 16, ptReference(scene, 20, 8, 16));
}

// At most 4 bounces, as BdptScenes.GlassCausticTorus (test_bdpt.cpp says why): the caustics seen
// directly through the dome (L S S D E) and the light's reflection in it. Pixel 172 sees the light
// in the dome's rim from a sliver of its area (4.0 in pt's 16384-sample image, made by s = 0
// alone): one render of 1024 passes with the default bootstrap (4 a pixel) gave it 0.16 (large
// steps only) or 0.13, 2.3 with 8192 passes, since b_hat was 83.6 against pt's image sum of 92.8
// and few chains find the sliver; 16 renders of 16 passes (24 of 16 with small steps) failed 3
// to 9 pixels. A bootstrap of 256 a pixel starts the chains near their stationary density and
// gives b_hat within a few percent (89.2), so the renders converge as bdpt's samples do: with
// seeds from 1000, 3000 and 7000, 1 of 400 pixels fails each time, a dim caustic pixel (2e-5 to
// 6e-3) that a render's 25600 deposits of e_d = 3.5e-3 mostly miss, a different one each time.
TEST_F(PssmltOverBdptScenes, GlassCausticTorus) {
    const Scene& scene = testScene("scenes/glass-caustic-torus.glb");
    RenderSettings s = largeStepsOnly(overBdpt(20, 64, 4));
    s.options["bootstrap"] = "256";
    expectUnbiased(scene, s, 16, ptReference(scene, 20, 4, 16));
}

}  // namespace
}  // namespace pmcr::test
