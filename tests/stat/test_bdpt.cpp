// Bidirectional path tracing: a seed gives the same image bit for bit; the furnace gives its
// analytic answer; the mean image equals path tracing's pixel by pixel (per-pixel z-tests,
// Mitsuba style) on cornell-glass, with punctual lights, under a sky with a sun, on lamp-room
// and glass-caustic-torus; and each (s, t) strategy alone, unweighted, is unbiased for the paths
// of its length, whose MIS-weighted strategies sum to the same answer (the weights of a path's
// strategies sum to 1). Path tracing's references take 1024 samples a pixel: with fewer, it
// misses the rare caustic paths on cornell-glass's ceiling that bdpt finds (16 renders of 64
// left pixels at 0.029 whose value is 0.045), and the z-test blames bdpt.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "gpu_test.h"
#include "render_test.h"
#include "statistics.h"

namespace pmcr::test {
namespace {

class BdptTest : public GpuTest {};
class BdptLights : public GpuTest {};
class BdptScenes : public GpuTest {};
class BdptStrategies : public GpuTest {};

RenderSettings bdptSettings(uint32_t spp, int size = 20, uint32_t maxDepth = 8) {
    return renderSettings("bdpt", size, size, spp, maxDepth);
}

// `renders` path-traced renders of `spp` samples: the reference.
ImageMoments ptReference(const Scene& scene, int size, uint32_t maxDepth, int renders, uint32_t spp = 64) {
    return renderMoments(scene, renderSettings("pt", size, size, spp, maxDepth), renders, 5000);
}

void expectUnbiased(const Scene& scene, const RenderSettings& s, int renders, const ImageMoments& reference,
                    double minPass = 0.9975) {
    const PixelTestResult r = zTestRenders(scene, s, renders, 1000, reference);
    EXPECT_GE(r.passFraction, minPass) << s.method << ": " << r.describe();
    std::printf("  %s (mis %s): %s\n", s.method.c_str(),
                s.options.count("mis") ? s.options.at("mis").c_str() : "power", r.describe().c_str());
}

TEST_F(BdptTest, SameSeedSameImageBitForBit) {
    const Scene& scene = testScene("scenes/cornell-glass.glb");
    const RenderSettings s = bdptSettings(4, 24);
    const auto a = renderForTest(scene, s);
    const auto b = renderForTest(scene, s);
    EXPECT_EQ(a.output.image.rgb, b.output.image.rgb);
    RenderSettings other = s;
    other.seed = 2;
    EXPECT_NE(a.output.image.rgb, renderForTest(scene, other).output.image.rgb);
    EXPECT_EQ(a.output.cameraSamples, 24u * 24u * 4u);
    EXPECT_EQ(a.stats["method_stats"]["light_subpaths"].get<uint64_t>(), 24u * 24u * 4u);
}

// Inside the furnace (a closed Lambertian enclosure of albedo 0.5 emitting 0.5) every pixel is
// 1 - 0.5^(D+1) with at most D bounces: the mean over pixels, with its standard error from the
// pixels' spread.
TEST_F(BdptTest, FurnaceGivesItsAnalyticValue) {
    const Scene& scene = testScene("scenes/furnace.glb");
    auto expectFurnace = [](const Image& image, double expected, const std::string& what) {
        double sum = 0.0, sumSq = 0.0;
        const size_t n = image.pixelCount();
        for (size_t i = 0; i < n; ++i) {
            const double y = image.rgb[3 * i + 1];
            ASSERT_TRUE(std::isfinite(y)) << what;
            sum += y;
            sumSq += y * y;
        }
        const double mean = sum / double(n);
        const double stderr = std::sqrt(std::max(0.0, sumSq / double(n) - mean * mean) / double(n));
        EXPECT_NEAR(mean, expected, 5.0 * stderr + 1e-4) << what << " (standard error " << stderr << ")";
    };
    for (uint32_t depth : {1u, 2u, 5u}) {
        const auto r = renderForTest(scene, bdptSettings(16, 24, depth));
        expectFurnace(r.output.image, 1.0 - std::pow(0.5, depth + 1), "bdpt max depth " + std::to_string(depth));
    }
    RenderSettings deep = bdptSettings(16, 24, 40);
    deep.rrDepth = 1;
    expectFurnace(renderForTest(scene, deep).output.image, 1.0 - std::pow(0.5, 41),
                  "bdpt with roulette from the first bounce");
}

TEST_F(BdptTest, UnbiasedOnCornellGlass) {
    const Scene& scene = testScene("scenes/cornell-glass.glb");
    const ImageMoments reference = ptReference(scene, 20, 8, 16, 1024);
    expectUnbiased(scene, bdptSettings(16), 16, reference);
}

TEST_F(BdptTest, UnbiasedWithTheBalanceHeuristic) {
    const Scene& scene = testScene("scenes/cornell-glass.glb");
    const ImageMoments reference = ptReference(scene, 20, 8, 16, 1024);
    RenderSettings s = bdptSettings(16);
    s.options["mis"] = "balance";
    expectUnbiased(scene, s, 16, reference);
}

// On the Lambertian Cornell box: path tracing reaches a punctual light by next-event estimation
// alone, so it cannot make caustics of one (L S+ D paths whose light is a delta), which bdpt's
// light tracing makes; on cornell-glass, bdpt is brighter than pt in those caustics, and right.
TEST_F(BdptLights, PointAndSpotLights) {
    const Scene scene = withPointAndSpotLights("scenes/cornell-classic.glb");
    expectUnbiased(scene, bdptSettings(16), 16, ptReference(scene, 20, 8, 16, 1024));
}

TEST_F(BdptLights, EnvironmentAndDirectionalLight) {
    const Scene scene = cornellGlassUnderSkyAndSun();
    expectUnbiased(scene, bdptSettings(16), 16, ptReference(scene, 20, 8, 16, 1024));
}

TEST_F(BdptScenes, LampRoom) {
    const Scene& scene = testScene("scenes/lamp-room.glb");
    expectUnbiased(scene, bdptSettings(16), 16, ptReference(scene, 20, 8, 16, 1024));
}

// At most 4 bounces: the caustic on the torus, seen through the dome (L S S D S S E, 5 bounces),
// is a path only the s = 0 strategy makes (every other one would connect at a delta vertex), the
// same estimator as pt's with the same fireflies; the z-test then checks little but tails.
// Shorter paths keep the caustics seen directly (L S S D E), which light tracing makes. 64
// samples a render: a pixel on the edge of the light's reflection in the dome sees it from a
// sliver of its area, which 16 renders of 16 samples mostly miss.
TEST_F(BdptScenes, GlassCausticTorus) {
    const Scene& scene = testScene("scenes/glass-caustic-torus.glb");
    expectUnbiased(scene, bdptSettings(64, 20, 4), 16, ptReference(scene, 20, 4, 16, 1024));
}

// The strategy images of one render, unweighted and weighted, by (s, t); strategies of more than
// maxDepth bounces must be black.
struct StrategyImages {
    std::map<std::pair<uint32_t, uint32_t>, std::vector<float>> unweighted, weighted;
};
StrategyImages strategyImages(const RenderResult& r, uint32_t maxDepth) {
    StrategyImages images;
    for (const auto& [name, image] : r.output.diagnostics) {
        unsigned s = 0, t = 0;
        EXPECT_EQ(std::sscanf(name.c_str(), "strategy-s%u-t%u", &s, &t), 2) << name;
        if (s + t - 2 > maxDepth) {
            for (float v : image.rgb) EXPECT_EQ(v, 0.0f) << name << " beyond --max-depth";
            continue;
        }
        auto& slot = name.find("-unweighted") != std::string::npos ? images.unweighted : images.weighted;
        slot[{s, t}] = image.rgb;
    }
    return images;
}

// Inside the furnace every strategy can make every path and every path of d bounces carries
// Le rho^d = 0.5^(d + 1) to the camera, so each (s, t) image alone, unweighted, has that mean
// over the pixels (Veach 1997 sec. 10.2: each strategy is an unbiased estimator of the paths of
// its length), and so do the MIS-weighted strategies of a depth together (the weights of a
// path's strategies sum to 1). The enclosure is a sphere, where G(x, y) is bounded, so every
// strategy has finite variance; in a box the unweighted connections blow up in the corners.
TEST_F(BdptStrategies, EachStrategyAloneIsUnbiasedForItsDepthInTheFurnace) {
    const uint32_t maxDepth = 3;
    RenderSettings s = bdptSettings(32, 24, maxDepth);
    s.options["strategy-images"] = "on";
    const StrategyImages images = strategyImages(renderForTest(testScene("scenes/furnace.glb"), s), maxDepth);
    ASSERT_EQ(images.unweighted.size(), 1u + 3u + 4u + 5u);  // depth 0 has (0, 2) alone: no (1, 1)
    auto meanAndError = [](const std::vector<float>& rgb) {
        double sum = 0.0, sumSq = 0.0;
        const size_t n = rgb.size() / 3;
        for (size_t i = 0; i < n; ++i) {
            sum += rgb[3 * i + 1];
            sumSq += double(rgb[3 * i + 1]) * rgb[3 * i + 1];
        }
        const double mean = sum / double(n);
        return std::pair<double, double>(mean, std::sqrt(std::max(0.0, sumSq / double(n) - mean * mean) / double(n)));
    };
    std::map<uint32_t, std::vector<float>> weightedSums;
    for (const auto& [st, rgb] : images.unweighted) {
        const uint32_t depth = st.first + st.second - 2;
        const double expected = std::pow(0.5, depth + 1);
        const auto [mean, error] = meanAndError(rgb);
        EXPECT_NEAR(mean, expected, 5.0 * error + 1e-4)
            << "strategy (" << st.first << ", " << st.second << ") unweighted, standard error " << error;
        std::printf("  (%u, %u) unweighted: %.5f (expected %.5f, standard error %.5f)\n", st.first, st.second,
                    mean, expected, error);
        auto& sum = weightedSums[depth];
        const auto& w = images.weighted.at(st);
        if (sum.empty()) sum.assign(w.size(), 0.0f);
        for (size_t i = 0; i < w.size(); ++i) sum[i] += w[i];
    }
    for (const auto& [depth, sum] : weightedSums) {
        const auto [mean, error] = meanAndError(sum);
        EXPECT_NEAR(mean, std::pow(0.5, depth + 1), 5.0 * error + 1e-4) << "weighted strategies of depth " << depth;
    }
}

// On the Cornell box the MIS-weighted strategies of each depth sum to the light of the paths of
// exactly that many bounces: per render the difference of path tracing at that many bounces and
// at one fewer (same seed; the differences of independent seeds are independent); per-pixel
// z-tests. So do next-event estimation (s = 1) and light tracing (t = 1) alone, unweighted: the
// other unweighted strategies are heavy-tailed there (a camera subpath that hits the small light
// after bounces, connections across a corner with their 1 / d^2), and the furnace tests them.
TEST_F(BdptStrategies, WeightedStrategiesOfEachDepthSumToItsLight) {
    const Scene& scene = testScene("scenes/cornell-classic.glb");
    const int size = 16, renders = 16;
    const uint32_t maxDepth = 3;
    std::map<uint32_t, ImageMoments> exact;  // per depth: pt(d) - pt(d - 1)
    for (int k = 0; k < renders; ++k) {
        std::vector<float> previous;
        for (uint32_t d = 0; d <= maxDepth; ++d) {
            RenderSettings pt = renderSettings("pt", size, size, 64, d);
            pt.seed = 5000 + uint32_t(k);
            std::vector<float> image = renderForTest(scene, pt).output.image.rgb;
            std::vector<float> difference = image;
            if (!previous.empty())
                for (size_t i = 0; i < image.size(); ++i) difference[i] -= previous[i];
            exact[d].add(difference);
            previous = image;
        }
    }
    std::map<std::pair<uint32_t, uint32_t>, ImageMoments> strategies;
    std::map<uint32_t, ImageMoments> weightedSums;
    for (int k = 0; k < renders; ++k) {
        RenderSettings s = bdptSettings(32, size, maxDepth);
        s.seed = 1000 + uint32_t(k);
        s.options["strategy-images"] = "on";
        const StrategyImages images = strategyImages(renderForTest(scene, s), maxDepth);
        std::map<uint32_t, std::vector<float>> sums;
        for (const auto& [st, rgb] : images.weighted) {
            auto& sum = sums[st.first + st.second - 2];
            if (sum.empty()) sum.assign(rgb.size(), 0.0f);
            for (size_t i = 0; i < sum.size(); ++i) sum[i] += rgb[i];
            if (st.first == 1 || st.second == 1) strategies[st].add(images.unweighted.at(st));
        }
        for (const auto& [depth, sum] : sums) weightedSums[depth].add(sum);
    }
    auto expectMatches = [&](const ImageMoments& moments, uint32_t depth, const std::string& what) {
        const ImageMoments& reference = exact[depth];
        const PixelTestResult r = pixelZTest(moments.mean(), moments.variance(), moments.count(),
                                             reference.mean(), reference.variance(), reference.count());
        EXPECT_GE(r.passFraction, 0.99) << what << ": " << r.describe();
        std::printf("  %s: %s\n", what.c_str(), r.describe().c_str());
    };
    for (const auto& [depth, moments] : weightedSums)
        expectMatches(moments, depth, "weighted strategies of depth " + std::to_string(depth));
    for (const auto& [st, moments] : strategies)
        expectMatches(moments, st.first + st.second - 2,
                      "(" + std::to_string(st.first) + ", " + std::to_string(st.second) + ") unweighted");
}

}  // namespace
}  // namespace pmcr::test
