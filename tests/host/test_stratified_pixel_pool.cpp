// PMC-ER's per-pixel stratified pool (render/stratified_pixel_pool.h): every pixel gets exactly
// one position per round, each position is uniform over its pixel (chi-square over many pools
// for one pixel, and over all positions of one pool), and consecutive positions are spread
// over the image.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "render/stratified_pixel_pool.h"
#include "statistics.h"

namespace pmcr::test {
namespace {

TEST(StratifiedPixelPool, EveryPixelGetsExactlyOnePositionPerRound) {
    for (auto [w, h] : {std::pair{16, 16}, std::pair{37, 11}, std::pair{1, 5}}) {
        const uint32_t rounds = 4;
        Pcg32 rng(7);
        StratifiedPixelPool pool(w, h, rounds, rng);
        ASSERT_EQ(pool.size(), uint64_t(rounds) * w * h);
        for (uint32_t r = 0; r < rounds; ++r) {
            std::vector<int> hits(size_t(w) * h, 0);
            // In uneven chunks, as the integrator asks for them.
            for (int taken = 0; taken < w * h;) {
                const uint32_t n = uint32_t(std::min(w * h - taken, 1 + taken % 7));
                for (const auto& p : pool.next(n)) {
                    ASSERT_GE(p.x, 0.0);
                    ASSERT_LT(p.x, double(w));
                    ASSERT_GE(p.y, 0.0);
                    ASSERT_LT(p.y, double(h));
                    ++hits[size_t(int(p.y)) * w + size_t(int(p.x))];
                }
                taken += int(n);
            }
            for (int c : hits) ASSERT_EQ(c, 1) << w << "x" << h << " round " << r;
        }
        EXPECT_EQ(pool.remaining(), 0u);
        EXPECT_TRUE(pool.next(5).empty());
    }
}

// Chi-square of positions within a pixel on a 8 x 8 grid of cells against uniform.
Chi2Result uniformWithinPixel(const std::vector<glm::dvec2>& offsets) {
    const int n = 8;
    std::vector<double> observed(n * n, 0.0), expected(n * n, double(offsets.size()) / (n * n));
    for (const auto& o : offsets)
        observed[size_t(std::min(n - 1, int(o.y * n))) * n + size_t(std::min(n - 1, int(o.x * n)))] += 1.0;
    return chi2Test(observed, expected);
}

TEST(StratifiedPixelPool, EachPositionIsUniformOverItsPixel) {
    // One pixel's position in each of 3 rounds, over many independently seeded pools.
    const int w = 9, h = 7, rounds = 3, pools = 4000;
    std::vector<std::vector<glm::dvec2>> offsets(rounds);
    for (int i = 0; i < pools; ++i) {
        Pcg32 rng(1000 + uint64_t(i), 3);
        StratifiedPixelPool pool(w, h, rounds, rng);
        int round = 0;
        for (const auto& p : pool.next(uint32_t(pool.size())))
            if (int(p.x) == 4 && int(p.y) == 2) offsets[size_t(round++)].push_back(p - glm::dvec2(4.0, 2.0));
        ASSERT_EQ(round, rounds);
    }
    const double level = sidakLevel(0.01, rounds + 1);
    for (int r = 0; r < rounds; ++r) {
        const Chi2Result c = uniformWithinPixel(offsets[size_t(r)]);
        EXPECT_GT(c.pValue, level) << "round " << r << ": " << c.describe();
    }
    // All positions of one large pool, folded into one pixel.
    Pcg32 rng(5);
    StratifiedPixelPool pool(64, 64, 2, rng);
    std::vector<glm::dvec2> all;
    for (const auto& p : pool.next(uint32_t(pool.size()))) all.push_back(p - glm::floor(p));
    const Chi2Result c = uniformWithinPixel(all);
    EXPECT_GT(c.pValue, level) << "all positions: " << c.describe();
}

TEST(StratifiedPixelPool, ConsecutivePositionsAreSpreadOverTheImage) {
    // On a power-of-two image, each aligned run of 4 positions of a round has one position in
    // each quadrant of the (toroidally shifted) image: pairwise at least half a side apart in x
    // or in y, up to the jitter within pixels.
    const int w = 32, h = 16;
    Pcg32 rng(11);
    StratifiedPixelPool pool(w, h, 2, rng);
    const auto p = pool.next(uint32_t(pool.size()));
    auto torus = [](double d, int side) { d = std::abs(d); return std::min(d, side - d); };
    for (size_t b = 0; b + 4 <= p.size(); b += 4)
        for (size_t i = b; i < b + 4; ++i)
            for (size_t j = i + 1; j < b + 4; ++j)
                EXPECT_TRUE(torus(std::floor(p[i].x) - std::floor(p[j].x), w) >= w / 2 ||
                            torus(std::floor(p[i].y) - std::floor(p[j].y), h) >= h / 2)
                    << "positions " << i << " and " << j;
}

}  // namespace
}  // namespace pmcr::test
