// Every method that takes punctual lights and the environment is unbiased with them: per-pixel
// z-tests (Mitsuba style, Sidak-corrected, at least 99.75% of pixels pass) of pt, direct, erpt
// pmc-er and mlt against path tracing with many samples, on cornell-glass (a glass sphere: caustic
// paths through it, so both of ERPT's perturbations run) with
//  (i)  a point and a spot light beside its area light: light vertices with a position, which
//       the lens perturbation reconnects to and the caustic perturbation starts from;
//  (ii) an environment image and a directional light shining in through the open front: light
//       vertices that are directions, which the lens perturbation keeps or retraces and the
//       caustic perturbation leaves alone (shaders/methods/energy_redistribution/*.glsl).
// (PMC-HI's z-tests with these lights are in test_pmc_hi.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "gpu_test.h"
#include "render_test.h"
#include "statistics.h"

namespace pmcr::test {
namespace {

// Two suites, so that ctest runs them side by side (their kernels differ by the lights anyway).
class ErLightsPunctual : public GpuTest {};
class ErLightsSky : public GpuTest {};

RenderSettings settingsFor(const std::string& method, uint32_t spp) {
    RenderSettings s = chainZTestSettings(method, spp);
    if (method == "erpt") {
        // Direct light redistributed too, and lens moves of 8 pixels: the paths E D L reconnect
        // to the light vertex, and far enough for its factor to matter. (Measured: dropping the
        // 1 / d^2 of the reconnection to a point light fails 18 of 400 pixels so, none with
        // the defaults, whose moves barely change d.)
        s.options["redistribute"] = "all";
        s.options["lens-radius"] = "8";
    } else if (method == "mlt") {
        // As erpt's.
        s.options["lens-radius"] = "8";
        s.options["direct"] = "chains";  // the sampler's density for direct paths to each light too
    } else if (method == "pmc-er") {
        s.options["population"] = "400";
        s.options["mutations"] = "4";
    }
    return s;
}

// `renders` path-traced renders of 64 samples (maxDepth 1 for direct, which estimates direct
// light only): the reference.
ImageMoments reference(const Scene& scene, uint32_t maxDepth, int renders) {
    RenderSettings pt = settingsFor("pt", 64);
    pt.maxDepth = maxDepth;
    return renderMoments(scene, pt, renders, 5000);
}

// The z-test of `renders` renders of `s` against `reference`.
void expectUnbiased(const Scene& scene, const RenderSettings& s, int renders,
                    const ImageMoments& reference) {
    const PixelTestResult r = zTestRenders(scene, s, renders, 1000, reference);
    EXPECT_GE(r.passFraction, 0.9975) << s.method << ": " << r.describe();
    std::printf("  %s: %s\n", s.method.c_str(), r.describe().c_str());
}

// Every method that takes the scene's lights, each against the reference of its depth.
// `directZTest` false: direct is instead checked to be pt at depth 1 (the same estimator with
// the same seed: equal up to float rounding). Under the sky, pixels whose light comes from rare
// events (grazing reflections off the glass that escape) make the per-pixel estimates
// heavy-tailed: pixel 334's green was 0 in all 256 samples of 16 direct renders of 16 spp, 0.002
// in 16 renders of 32, 0.011 and 0.013 in single renders of 1024 and 2048, 0.026 in the 16
// references; direct failed that pixel (the 0.25% the test allows) and with 48 references a
// second one, flukes of an estimator identical to pt's (which fails none), not bias. Direct's
// unbiasedness under an image sky is tested against the analytic answer in
// test_environment_render.cpp.
void expectAllUnbiased(const Scene& scene, bool directZTest) {
    const ImageMoments full = reference(scene, 8, 16);
    expectUnbiased(scene, settingsFor("pt", 32), 16, full);
    if (directZTest) {
        expectUnbiased(scene, settingsFor("direct", 32), 16, reference(scene, 1, 16));
    } else {
        RenderSettings pt1 = settingsFor("pt", 8);
        pt1.maxDepth = 1;
        const Image direct = renderForTest(scene, settingsFor("direct", 8)).output.image;
        const Image pt = renderForTest(scene, pt1).output.image;
        ASSERT_EQ(direct.rgb.size(), pt.rgb.size());
        for (size_t i = 0; i < pt.rgb.size(); ++i) {  // equal up to float summation order
            ASSERT_NEAR(direct.rgb[i], pt.rgb[i], 1e-5f * (1.0f + std::abs(pt.rgb[i]))) << "value " << i;
        }
    }
    expectUnbiased(scene, settingsFor("erpt", 16), 40, full);
    expectUnbiased(scene, settingsFor("pmc-er", 16), 40, full);
    expectUnbiased(scene, settingsFor("mlt", 16), 40, full);
}

TEST_F(ErLightsPunctual, PointAndSpotLights) { expectAllUnbiased(cornellGlassWithPointLights(), true); }

TEST_F(ErLightsSky, EnvironmentAndDirectionalLight) { expectAllUnbiased(cornellGlassUnderSkyAndSun(), false); }

}  // namespace
}  // namespace pmcr::test
