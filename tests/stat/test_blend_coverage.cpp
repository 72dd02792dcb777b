// alphaMode BLEND as stochastic coverage (shaders/common/bsdf.glsl LOBE_PASS): a card of
// coverage 0.3 in front of an emitter of radiance 1 lets 70% of it through, per pixel, for every
// method pmcr has. The card is black, so the light it reflects is none and each pixel's answer
// is exactly 0.7 (a reference without variance).
//
// The choice this documents: a pass through a BLEND surface is a specular transmission event
// of eta 1 (the material is coverage * surface + (1 - coverage) * pass), not an event outside
// the path. Path tracing and photon mapping sample it as a delta lobe, a shadow ray stops at the
// surface as at glass, and the Metropolis methods (erpt, mlt, pssmlt, pmc-er), whose targets
// evaluate a path deterministically, see a pass as one more specular vertex of their paths, so
// their densities and Jacobians hold unchanged (test_erpt_densities.cpp checks the caustic
// Jacobian through a pass). The expected value over the pass choice is the coverage-weighted
// image a rasterizer's compositing approximates; no estimator draws a coverage of its own that
// another could not evaluate.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "gpu_test.h"
#include "render/methods.h"
#include "render_test.h"
#include "scene_builder.h"

namespace pmcr::test {
namespace {

constexpr float kCoverage = 0.3f;

// An emitter quad of radiance 1 facing the camera at z = -3, a black BLEND card of coverage 0.3
// at z = -1 covering the whole view, the camera at z = 5 looking down -z.
Scene cardScene() {
    Scene s;
    s.path = "blend-card.gltf";
    gpu::Material card = testMaterial(glm::vec3(0.0f), true);
    card.baseColor = glm::vec3(0.0f);
    card.flags |= gpu::MATERIAL_BLEND;
    card.coverage = kCoverage;
    gpu::Material light = testMaterial(glm::vec3(1.0f));
    light.baseColor = glm::vec3(0.0f);
    s.materials = {card, light};
    addTriangle(s, {-10, -10, -1}, {10, -10, -1}, {10, 10, -1}, 0);
    addTriangle(s, {-10, -10, -1}, {10, 10, -1}, {-10, 10, -1}, 0);
    addTriangle(s, {-20, -20, -3}, {20, -20, -3}, {20, 20, -3}, 1);  // facing +z
    addTriangle(s, {-20, -20, -3}, {20, 20, -3}, {-20, 20, -3}, 1);
    Camera camera;
    camera.position = glm::vec3(0, 0, 5);
    camera.yfov = 0.6f;
    s.cameras.push_back(camera);
    finalizeScene(s);
    return s;
}

class BlendCoverage : public GpuTest {};

constexpr int kWidth = 12, kHeight = 8, kRenders = 16;
constexpr uint32_t kSpp = 8;

// Independent path-traced renders of the card scene (the reference of both tests).
ImageMoments ptRenders(const Scene& scene) {
    return renderMoments(scene, renderSettings("pt", kWidth, kHeight, kSpp, 4), kRenders, 5000);
}

// Path tracing's image mean over independent renders is 0.7, within four standard errors of the
// mean over renders.
TEST_F(BlendCoverage, CardOfAlphaPointThreeTransmitsSeventyPercent) {
    const Scene scene = cardScene();
    const ImageMoments reference = ptRenders(scene);
    double sum = 0.0, sumSq = 0.0;
    const std::vector<float> mean = reference.mean(), variance = reference.variance();
    for (size_t i = 1; i < mean.size(); i += 3) {
        sum += mean[i];
        sumSq += variance[i];
    }
    const double pixels = double(kWidth * kHeight);
    const double imageMeanOfRenders = sum / pixels;
    // The pixels' estimates are independent: the image mean's variance over renders is the sum
    // of their variances over pixels^2, divided by the renders averaged.
    const double standardError = std::sqrt(sumSq / (pixels * pixels) / kRenders);
    std::printf("  pt image mean over %d renders: %.5f +- %.5f (expected %.2f)\n", kRenders,
                imageMeanOfRenders, standardError, 1.0 - kCoverage);
    EXPECT_NEAR(imageMeanOfRenders, 1.0 - kCoverage, 4.0 * standardError + 1e-4);
}

// Every method's mean image matches path tracing's per pixel (Sidak-corrected z-test, at least
// 99.75% of pixels pass). The comparison is against path-traced renders rather than the exact
// 0.7: each sample is 0 or 1 and the samplers stratify the choice, so a pixel's renders take two
// values only and an exact reference (of no variance) would leave the z-test with the two-point
// variance of the method's renders alone.
TEST_F(BlendCoverage, EveryMethodMatchesPathTracingPerPixel) {
    const Scene scene = cardScene();
    const ImageMoments reference = ptRenders(scene);
    int tested = 0;
    for (const MethodInfo& method : methods()) {
        if (!method.create) continue;  // planned, not implemented
        SCOPED_TRACE(method.name);
        const RenderSettings s = renderSettings(method.name, kWidth, kHeight, kSpp, 4);
        // mmlt's renders here are heavy-tailed (only s = 0 carries the light, a proposal picks it
        // once in three): with 16 renders, 16-render sets failed 1 to 2 of 96 pixels, all darker,
        // in 1 of 6 seed bases (2026-11-29, before and after its bootstrap became stratified;
        // 32 renders of 8 or 16 of 32 passes no better), the same pixels agreeing in other sets;
        // with 64 renders, 4 of 4 sets passed (worst |z| 3.05 to 3.49).
        const int renders = method.name == "mmlt" ? 64 : kRenders;
        const PixelTestResult r = zTestRenders(scene, s, renders, 1000, reference);
        const glm::dvec3 m = imageMean(renderForTest(scene, s).output.image);
        std::printf("  %-14s image mean %.4f; %s\n", method.name.c_str(), m.y, r.describe().c_str());
        EXPECT_GE(r.passFraction, 0.9975) << r.describe();
        ++tested;
    }
    EXPECT_GE(tested, 13);
}

}  // namespace
}  // namespace pmcr::test
