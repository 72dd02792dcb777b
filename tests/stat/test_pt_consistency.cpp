// Path tracing's determinism, and two different estimators of the same integral agreeing
// pixel by pixel: pt with one bounce (one light sample and one BSDF sample, one-sample MIS per
// vertex) and direct (n light + n BSDF samples, multi-sample MIS) both estimate direct lighting.
#include <gtest/gtest.h>

#include "gpu_test.h"
#include "render_test.h"
#include "statistics.h"

namespace pmcr::test {
namespace {

class PtConsistency : public GpuTest {};

TEST_F(PtConsistency, SameSeedSameImageBitForBit) {
    RenderSettings s;
    s.method = "pt";
    s.spp = 2;
    s.width = 64;
    s.height = 64;
    auto a = renderForTest(testScene("scenes/cornell-spheres.glb"), s);
    auto b = renderForTest(testScene("scenes/cornell-spheres.glb"), s);
    EXPECT_EQ(a.output.image.rgb, b.output.image.rgb);
    s.seed = 2;
    auto c = renderForTest(testScene("scenes/cornell-spheres.glb"), s);
    EXPECT_NE(a.output.image.rgb, c.output.image.rgb);
}

// Independent renders (different seeds) give per-pixel means and variances for both methods.
void moments(const Scene& scene, RenderSettings s, int renders, ImageMoments& m) {
    for (int i = 0; i < renders; ++i) {
        s.seed = 1000u + uint32_t(i);
        m.add(renderForTest(scene, s).output.image.rgb);
    }
}

TEST_F(PtConsistency, OneBouncePathTracingEqualsDirectLighting) {
    const Scene& scene = testScene("scenes/cornell-spheres.glb");
    RenderSettings pt;
    pt.method = "pt";
    pt.maxDepth = 1;
    pt.spp = 8;
    pt.width = 24;
    pt.height = 24;
    RenderSettings direct = pt;
    direct.method = "direct";
    direct.maxDepth = 16;
    direct.options["light-samples"] = "2";
    direct.spp = 4;
    const int renders = 24;
    ImageMoments a, b;
    moments(scene, pt, renders, a);
    moments(scene, direct, renders, b);
    auto result = pixelZTest(a.mean(), a.variance(), renders, b.mean(), b.variance(), renders);
    EXPECT_GE(result.passFraction, 0.9975) << result.describe();
}

}  // namespace
}  // namespace pmcr::test
