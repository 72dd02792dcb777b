// Path tracing and direct lighting against the furnaces' analytic answer
// (scenes/README.md): inside a closed Lambertian enclosure of albedo 0.5 that also emits 0.5,
// every camera ray sees L_D = Le * sum_{k=0}^{D} rho^k = 1 - 0.5^(D+1) with at most D bounces.
#include <gtest/gtest.h>

#include <cmath>

#include "gpu_test.h"
#include "render_test.h"
#include "statistics.h"

namespace pmcr::test {
namespace {

double furnaceAnswer(int maxDepth) { return 1.0 - std::pow(0.5, maxDepth + 1); }

// Every pixel of a furnace has the same expectation, so the pixels are independent estimates
// of it: their mean must match within a few standard errors (from their own spread).
void expectFurnace(const Image& image, double expected, const std::string& what) {
    double sum = 0.0, sumSq = 0.0;
    const size_t n = image.pixelCount();
    for (size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) {
            const double v = image.rgb[3 * i + c];
            ASSERT_TRUE(std::isfinite(v)) << what;
        }
        const double y = image.rgb[3 * i + 1];  // grey scene: channels are equal in expectation
        sum += y;
        sumSq += y * y;
    }
    const double mean = sum / double(n);
    const double variance = std::max(0.0, sumSq / double(n) - mean * mean);
    const double stderr = std::sqrt(variance / double(n));
    // 5 sigma, plus float summation slack.
    EXPECT_NEAR(mean, expected, 5.0 * stderr + 1e-5)
        << what << ": mean " << mean << " expected " << expected << " (standard error " << stderr << ")";
}

class PtFurnace : public GpuTest {};

TEST_F(PtFurnace, EmptyFurnaceAtSeveralDepths) {
    for (int depth : {1, 2, 5}) {
        RenderSettings s;
        s.method = "pt";
        s.spp = 16;
        s.maxDepth = uint32_t(depth);
        auto r = renderForTest(testScene("scenes/furnace.glb"), s);
        expectFurnace(r.output.image, furnaceAnswer(depth), "pt max depth " + std::to_string(depth));
    }
}

TEST_F(PtFurnace, RussianRouletteKeepsTheDeepAnswer) {
    RenderSettings s;
    s.method = "pt";
    s.spp = 32;
    s.maxDepth = 64;
    s.rrDepth = 1;
    auto r = renderForTest(testScene("scenes/furnace.glb"), s);
    expectFurnace(r.output.image, furnaceAnswer(64), "pt with roulette from the first bounce");
}

TEST_F(PtFurnace, FurnaceWithInnerSphere) {
    RenderSettings s;
    s.method = "pt";
    s.spp = 16;
    s.maxDepth = 4;
    auto r = renderForTest(testScene("scenes/furnace-sphere.glb"), s);
    expectFurnace(r.output.image, furnaceAnswer(4), "pt furnace-sphere");
}

TEST_F(PtFurnace, DirectLightingIsOneBounce) {
    for (const char* scene : {"scenes/furnace.glb", "scenes/furnace-sphere.glb"}) {
        RenderSettings s;
        s.method = "direct";
        s.spp = 16;
        s.options["light-samples"] = "2";
        auto r = renderForTest(testScene(scene), s);
        expectFurnace(r.output.image, furnaceAnswer(1), std::string("direct ") + scene);
    }
}

}  // namespace
}  // namespace pmcr::test
