// Renders scenes in-process on the shared validated test context, exactly as `pmcr render` does.
#pragma once

#include <string>
#include <utility>

#include "image/image.h"
#include "render/renderer.h"
#include "render/settings.h"
#include "scene/scene.h"
#include "statistics.h"

namespace pmcr::test {

// Loads a scene from the source tree once per test binary (cached by path).
const Scene& testScene(const std::string& relativePath);

// cornell-glass with a point light near the ceiling and a spot light aimed at the sphere's side
// beside its area light (intensities in proportion to the box's size^2): light vertices with a
// position.
Scene cornellGlassWithPointLights();
// The same two lights, placed by the bounding box, added to the scene at `relativePath`.
Scene withPointAndSpotLights(const std::string& relativePath);

// cornell-glass under a random 16 x 8 sky with a sun pixel (randomSkyImage seed 29) and a
// directional light along the camera's view, tilted down, shining in through the open front:
// light vertices that are directions.
Scene cornellGlassUnderSkyAndSun();

// Settings for a small test render: `method` at width x height, `spp`, at most `maxDepth` bounces.
RenderSettings renderSettings(const std::string& method, int width, int height, uint32_t spp,
                              uint32_t maxDepth = RenderSettings{}.maxDepth);

// The chain methods' z-test settings on a 20 x 20 image of at most 8 bounces: `method` with
// `spp`, and for erpt and mlt the caustic perturbation on every path it applies to (mutation
// mix; erpt's chains of 20 with 4 mutations a pixel, mlt's bootstrap as large as the
// references' samples, tests/stat/test_mlt.cpp). Shared by the z-tests of the lights
// (test_er_lights.cpp) and of the material extensions (test_material_extensions.cpp).
RenderSettings chainZTestSettings(const std::string& method, uint32_t spp);

// pssmlt's and mmlt's bookkeeping on cornell-glass at 32 x 32 with 100 chains and 3 passes of
// `settings` (--bootstrap samples per pixel, of each depth for mmlt):
// each pass about one mutation per pixel (10 steps of 100 chains), every mutation depositing
// e_d in all (within `energyTolerance`, relative), none dropped, both kinds of step proposed
// (30% large) and accepted, and b_hat close to the image's total luminance. Over pt and over
// bdpt (test_pssmlt.cpp, test_pssmlt_bdpt.cpp) and mmlt's (test_mmlt.cpp).
void expectPssmltMutationsDepositOneUnit(RenderSettings settings, double energyTolerance);

// Renders `scene` with `settings` (size resolved from the scene when 0).
RenderResult renderForTest(const Scene& scene, RenderSettings settings);

// Renders a Metropolis method's `settings` (spp passes) with --passes-per-batch 1 and `together`
// and expects the same image bit for bit, every pass completed and the count taken (the chains
// carry their random numbers between submissions and the splat film sums integer quanta; issue
// 38). Returns the two results, one at a time first, for the method's own checks.
std::pair<RenderResult, RenderResult> expectPassesPerBatchKeepTheImage(const Scene& scene, RenderSettings settings,
                                                                       int together);

// Mean of all pixels' luminance... and of each channel.
glm::dvec3 imageMean(const Image& image);

// Per-pixel moments of `renders` independent renders, seeds firstSeed, firstSeed + 1, ...
ImageMoments renderMoments(const Scene& scene, RenderSettings settings, int renders, uint32_t firstSeed);

// A figure's mean over independent renders and the standard error of that mean.
struct MeanEstimate {
    double mean = 0.0;
    double standardError = 0.0;
};
// The image mean's green channel (a grey furnace's answer) over `renders` independent renders,
// seeds firstSeed, firstSeed + 1, ...
MeanEstimate meanOverRenders(const Scene& scene, RenderSettings settings, int renders, uint32_t firstSeed);

// The Mitsuba-style per-pixel z-test (pixelZTest) of the mean of independent renders of
// `method` against independent renders of `baseline`.
PixelTestResult zTestRenders(const Scene& scene, const RenderSettings& method, int renders,
                             uint32_t firstSeed, const ImageMoments& baseline);

}  // namespace pmcr::test
