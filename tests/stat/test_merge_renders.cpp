// `pmcr merge` on real renders: pieces of 1 and 3 samples per pixel (their own seeds), written
// with their stats and merged from the files, against one render of 4 samples per pixel.
//
// The furnace (scenes/README.md) makes every pixel an independent estimate of the same value
// (1 - 0.5^(D+1), D = 64 with roulette from the first bounce), so one image is 1024 replicas:
// their mean and spread test the merged image against the full render and the analytic answer.
#include <gtest/gtest.h>

#include <cmath>

#include "gpu_test.h"
#include "metrics/merge.h"
#include "render_test.h"
#include "test_util.h"

namespace pmcr::test {
namespace {

class MergeRenders : public GpuTest {};

struct PixelSpread {
    double mean = 0.0;
    double standardError = 0.0;
};

// Mean of the green channel over pixels and its standard error (pixels as replicas).
PixelSpread spread(const Image& image) {
    double sum = 0.0, sumSq = 0.0;
    const double n = double(image.pixelCount());
    for (size_t i = 0; i < image.pixelCount(); ++i) {
        const double v = image.rgb[3 * i + 1];
        sum += v;
        sumSq += v * v;
    }
    const double mean = sum / n;
    return {mean, std::sqrt(std::max(0.0, sumSq / n - mean * mean) / n)};
}

std::filesystem::path renderPiece(const std::filesystem::path& dir, uint32_t seed, uint32_t spp) {
    RenderSettings s;
    s.method = "pt";
    s.spp = spp;
    s.seed = seed;
    s.width = 32;
    s.height = 32;
    s.maxDepth = 64;
    s.rrDepth = 1;
    const RenderResult r = renderForTest(testScene("scenes/furnace.glb"), s);
    const auto path = dir / ("seed" + std::to_string(seed) + ".exr");
    writeRenderOutputs(r, resolveOutputPaths("furnace.glb", path, std::nullopt, true, 0.0f));
    return path;
}

TEST_F(MergeRenders, PiecesOfOneAndThreeSamplesMergeIntoOneRenderOfFour) {
    const auto dir = tempDir("merge-renders");
    const RenderPiece a = readRenderPiece(renderPiece(dir, 11, 1));
    const RenderPiece b = readRenderPiece(renderPiece(dir, 12, 3));
    const RenderPiece full = readRenderPiece(renderPiece(dir, 13, 4));
    const MergedRender merged = mergeRenders({a, b});

    // The weights are the sample counts read back from the stats files: exactly (A + 3B) / 4.
    // Equal weights, or weights from anything else, fail here.
    ASSERT_EQ(merged.image.rgb.size(), a.image.rgb.size());
    for (size_t i = 0; i < merged.image.rgb.size(); ++i) {
        const double expected = (double(a.image.rgb[i]) + 3.0 * double(b.image.rgb[i])) / 4.0;
        ASSERT_NEAR(merged.image.rgb[i], expected, 1e-6 * std::max(1.0, expected)) << i;
    }
    EXPECT_EQ(merged.stats["samples"], full.stats["samples"]);
    EXPECT_DOUBLE_EQ(merged.stats["spp"].get<double>(), 4.0);

    // Statistically the merged image is the full render: same expectation (two-sample z-test
    // over pixels, 4 sigma), both at the furnace's answer (5 sigma). The pieces differ enough
    // that the weights matter: the 1-spp piece alone has four times the variance.
    const PixelSpread m = spread(merged.image), f = spread(full.image), one = spread(a.image);
    const double answer = 1.0 - std::pow(0.5, 65);
    EXPECT_GT(m.standardError, 0.0);
    EXPECT_NEAR(m.mean, f.mean, 4.0 * std::hypot(m.standardError, f.standardError))
        << "merged " << m.mean << " +- " << m.standardError << ", full " << f.mean << " +- "
        << f.standardError;
    EXPECT_NEAR(m.mean, answer, 5.0 * m.standardError + 1e-5);
    EXPECT_NEAR(f.mean, answer, 5.0 * f.standardError + 1e-5);
    // The merged image has about the spread of 4 samples per pixel: its standard error is about
    // half the 1-spp piece's (variance ratio 4; 3 with equal weights, 1.7 with swapped ones).
    EXPECT_GT(one.standardError / m.standardError, std::sqrt(2.0))
        << "1-spp piece " << one.standardError << ", merged " << m.standardError;
}

}  // namespace
}  // namespace pmcr::test
