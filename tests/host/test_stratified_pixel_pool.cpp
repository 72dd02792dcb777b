// PMC-ER's per-pixel stratified pool (methods/pmc_er/stratified_pixel_pool.h): every pixel gets
// exactly one sample per round, the rounds of consecutive passes are consecutive samples of the
// pixel's sampler sequence (whose points are uniform over the pixel and stratified among
// themselves: tests/gpu/test_sampler.cpp), and consecutive samples are spread over the image.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "methods/pmc_er/stratified_pixel_pool.h"

namespace pmcr::test {
namespace {

TEST(StratifiedPixelPool, EveryPixelGetsExactlyOneSamplePerRound) {
    for (auto [w, h] : {std::pair{16, 16}, std::pair{37, 11}, std::pair{1, 5}}) {
        const uint32_t rounds = 4, firstSample = 8;
        Pcg32 rng(7);
        StratifiedPixelPool pool(w, h, rounds, firstSample, rng);
        ASSERT_EQ(pool.size(), uint64_t(rounds) * w * h);
        for (uint32_t r = 0; r < rounds; ++r) {
            std::vector<int> hits(size_t(w) * h, 0);
            // In uneven chunks, as the integrator asks for them.
            for (int taken = 0; taken < w * h;) {
                const uint32_t n = uint32_t(std::min(w * h - taken, 1 + taken % 7));
                for (const PoolSample& s : pool.next(n)) {
                    ASSERT_LT(s.pixel, uint32_t(w * h));
                    ASSERT_EQ(s.sampleIndex, firstSample + r);
                    ++hits[s.pixel];
                }
                taken += int(n);
            }
            for (int c : hits) ASSERT_EQ(c, 1) << w << "x" << h << " round " << r;
        }
        EXPECT_EQ(pool.remaining(), 0u);
        EXPECT_TRUE(pool.next(5).empty());
    }
}

TEST(StratifiedPixelPool, PassesContinueThePixelsSampleSequences) {
    // Pass q of k rounds takes samples q k .. q k + k - 1: over a render each pixel gets samples
    // 0, 1, 2, ... of its sequence once each.
    const int w = 5, h = 3;
    const uint32_t rounds = 3, passes = 4;
    std::vector<std::vector<int>> seen(size_t(w * h), std::vector<int>(rounds * passes, 0));
    for (uint32_t q = 0; q < passes; ++q) {
        Pcg32 rng(q);
        StratifiedPixelPool pool(w, h, rounds, q * rounds, rng);
        for (const PoolSample& s : pool.next(uint32_t(pool.size()))) ++seen[s.pixel][s.sampleIndex];
    }
    for (const auto& pixel : seen)
        for (int c : pixel) EXPECT_EQ(c, 1);
}

TEST(StratifiedPixelPool, ConsecutiveSamplesAreSpreadOverTheImage) {
    // On a power-of-two image, each aligned run of 4 samples of a round has one pixel in each
    // quadrant of the (toroidally shifted) image: pairwise half a side apart in x or in y.
    const int w = 32, h = 16;
    Pcg32 rng(11);
    StratifiedPixelPool pool(w, h, 2, 0, rng);
    const auto s = pool.next(uint32_t(pool.size()));
    auto torus = [](int d, int side) { d = std::abs(d); return std::min(d, side - d); };
    for (size_t b = 0; b + 4 <= s.size(); b += 4)
        for (size_t i = b; i < b + 4; ++i)
            for (size_t j = i + 1; j < b + 4; ++j) {
                const int xi = int(s[i].pixel) % w, yi = int(s[i].pixel) / w;
                const int xj = int(s[j].pixel) % w, yj = int(s[j].pixel) / w;
                EXPECT_TRUE(torus(xi - xj, w) >= w / 2 || torus(yi - yj, h) >= h / 2)
                    << "samples " << i << " and " << j;
            }
}

TEST(StratifiedPixelPool, LanesSplitTheSequence) {
    // Lane l of L takes positions l, l + L, ... of the one-lane sequence, in uneven chunks:
    // together the lanes take every position once, with the same pixels and samples.
    const int w = 7, h = 5;
    const uint32_t rounds = 3;
    Pcg32 rng(5);
    Pcg32 copy = rng;
    StratifiedPixelPool whole(w, h, rounds, 6, rng);
    const auto all = whole.next(uint32_t(whole.size()));
    for (uint32_t lanes : {2u, 3u, 4u}) {
        uint64_t total = 0;
        for (uint32_t lane = 0; lane < lanes; ++lane) {
            Pcg32 laneRng = copy;
            StratifiedPixelPool pool(w, h, rounds, 6, laneRng, lane, lanes);
            total += pool.size();
            std::vector<PoolSample> got;
            for (uint32_t n = 1; pool.remaining() > 0; ++n)
                for (const PoolSample& s : pool.next(n)) got.push_back(s);
            ASSERT_EQ(got.size(), pool.size());
            for (size_t i = 0; i < got.size(); ++i) {
                EXPECT_EQ(got[i].pixel, all[lane + i * lanes].pixel);
                EXPECT_EQ(got[i].sampleIndex, all[lane + i * lanes].sampleIndex);
            }
        }
        EXPECT_EQ(total, all.size()) << lanes << " lanes";
    }
}

}  // namespace
}  // namespace pmcr::test
