// PMC-PT's host side (methods/pmc_pt/pixel_population.h) against direct references: disk sampling
// and a step's proposals against their expected counts over brute-force pixel disks (chi-square),
// the alpha and beta updates against the paper's formulas, the pool's stratification and the
// resampling proportions; and the option lists of radii.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.h"
#include "image/tvi.h"
#include "methods/pmc_pt/pixel_population.h"
#include "render/settings.h"
#include "statistics.h"

namespace pmcr::test {
namespace {

// The clipped pixel disk by brute force: every pixel of the image tested.
std::vector<glm::ivec2> pixelDisk(glm::ivec2 c, double r, int w, int h) {
    std::vector<glm::ivec2> pixels;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double dx = x - c.x, dy = y - c.y;
            if (dx * dx + dy * dy <= r * r) pixels.push_back({x, y});
        }
    return pixels;
}

// Lists of numbers in options ("5,10,50" or "5/10/50", as pmcr bench --methods needs) and the
// radii checks built on them.
TEST(PixelPopulation, NumberListsAndRadiiParse) {
    EXPECT_EQ(parseNumberList("x", "5,10,50"), (std::vector<double>{5.0, 10.0, 50.0}));
    EXPECT_EQ(parseNumberList("x", "0.5/0.25/0"), (std::vector<double>{0.5, 0.25, 0.0}));
    for (const char* bad : {"", "5,", ",5", "5//10", "5,x", "1e999", "nan"})
        EXPECT_THROW(parseNumberList("x", bad), Error) << bad;
    EXPECT_EQ(parseRadii("3/10"), (std::vector<double>{3.0, 10.0}));
    for (const char* bad : {"0", "5,-1", "1,2,3,4", "", "5,"}) EXPECT_THROW(parseRadii(bad), Error) << bad;
}

TEST(PixelPopulation, PixelDiskSamplesAreUniformOverTheClippedDisk) {
    const int w = 24, h = 16;
    Pcg32 rng(7);
    for (const auto& [c, r] : std::vector<std::pair<glm::ivec2, double>>{
             {{12, 8}, 5}, {{1, 1}, 10}, {{23, 8}, 50}}) {
        const auto disk = pixelDisk(c, r, w, h);
        std::vector<double> observed(size_t(w * h), 0.0), expected(size_t(w * h), 0.0);
        const int n = 40000;
        for (const auto& p : disk) expected[size_t(p.y * w + p.x)] = double(n) / disk.size();
        for (int i = 0; i < n; ++i) {
            const glm::ivec2 p = samplePixelDisk(c, r, w, h, rng);
            ASSERT_TRUE(p.x >= 0 && p.x < w && p.y >= 0 && p.y < h);
            ASSERT_GT(expected[size_t(p.y * w + p.x)], 0.0) << "outside the disk";
            observed[size_t(p.y * w + p.x)] += 1.0;
        }
        std::vector<double> o, e;
        for (size_t i = 0; i < expected.size(); ++i)
            if (expected[i] > 0.0) o.push_back(observed[i]), e.push_back(expected[i]);
        const Chi2Result chi2 = chi2Test(o, e);
        EXPECT_GT(chi2.pValue, sidakLevel(0.01, 3)) << chi2.describe();
    }
}

std::array<RunningStats, kMaxPopulationRadii> tagged(std::vector<std::vector<double>> values) {
    std::array<RunningStats, kMaxPopulationRadii> t{};
    for (size_t k = 0; k < values.size(); ++k)
        for (double v : values[k]) t[k].add(v);
    return t;
}

TEST(PixelPopulation, AlphaFollowsTheInverseVariances) {
    // Variances 2, 8 and 0 (PMC-PT sec. 4.3.3): alpha' = 1/2, 1/8, 0.
    const auto t = tagged({{1, 3}, {0, 4}, {5, 5, 5}});
    ASSERT_DOUBLE_EQ(t[0].variance(), 2.0);
    ASSERT_DOUBLE_EQ(t[1].variance(), 8.0);
    const double eps = 0.01;
    const auto a = adaptAlpha(t, 3, eps, {1.0 / 3, 1.0 / 3, 1.0 / 3});
    const double sum = 0.5 + 0.125, norm = 3 * eps + 1 - eps;
    EXPECT_NEAR(a[0], (eps + (1 - eps) * 0.5 / sum) / norm, 1e-12);
    EXPECT_NEAR(a[1], (eps + (1 - eps) * 0.125 / sum) / norm, 1e-12);
    EXPECT_NEAR(a[2], eps / norm, 1e-12);
    EXPECT_NEAR(a[0] + a[1] + a[2], 1.0, 1e-12);
    // A component with one sample has no variance yet; nothing learned keeps the weights.
    const auto b = adaptAlpha(tagged({{1}, {2}, {}}), 3, eps, {0.2, 0.3, 0.5});
    EXPECT_EQ(b[0], 0.2);
    EXPECT_EQ(b[2], 0.5);
    // Two components.
    const auto c = adaptAlpha(tagged({{0, 2}, {0, 1}}), 2, 0.0, {0.5, 0.5});
    EXPECT_NEAR(c[0], 0.5 / 2.5, 1e-12);
    EXPECT_NEAR(c[1], 2.0 / 2.5, 1e-12);
}

TEST(PixelPopulation, BetaIsVarianceOverTvi) {
    std::vector<RunningStats> pixels(4);
    pixels[0].add(0.0), pixels[0].add(2.0);   // variance 2
    pixels[1].add(1.0), pixels[1].add(1.0);   // variance 0
    pixels[2].add(0.5);                       // one sample: no variance
    pixels[3].add(0.0), pixels[3].add(10.0);  // variance 50
    const std::vector<double> estimate = {1.0, 1.0, 0.5, 5.0};
    PixelImportance beta;
    beta.update(pixels, estimate);
    const double b0 = 2.0 / tvi(1.0), b3 = 50.0 / tvi(5.0);
    EXPECT_NEAR(beta.probability(0), b0 / (b0 + b3), 1e-12);
    EXPECT_EQ(beta.probability(1), 0.0);
    EXPECT_EQ(beta.probability(2), 0.0);
    EXPECT_NEAR(beta.probability(3), b3 / (b0 + b3), 1e-12);
    Pcg32 rng(3);
    std::vector<double> observed(4, 0.0), expected(4);
    const int n = 20000;
    for (int i = 0; i < n; ++i) observed[beta.samplePixel(rng.nextDouble())] += 1.0;
    for (int p = 0; p < 4; ++p) expected[p] = n * beta.probability(uint32_t(p));
    EXPECT_EQ(observed[1] + observed[2], 0.0);
    const Chi2Result chi2 = chi2Test({observed[0], observed[3]}, {expected[0], expected[3]});
    EXPECT_GT(chi2.pValue, 0.001) << chi2.describe();
}

TEST(PixelPopulation, PoolCoversTheImageEvenly) {
    PositionPool pool(8, 6);
    Pcg32 rng(11);
    std::vector<int> counts(48, 0);
    for (int chunk = 0; chunk < 4; ++chunk)
        for (const glm::dvec2& p : pool.next(1200, rng)) {
            ASSERT_TRUE(p.x >= 0 && p.x < 8 && p.y >= 0 && p.y < 6);
            ++counts[int(p.y) * 8 + int(p.x)];
        }
    // 100 per pixel; a stratified chunk is far more even than Poisson's +-30 (3 sigma).
    for (int c : counts) {
        EXPECT_GE(c, 90);
        EXPECT_LE(c, 110);
    }
}

PopulationSettings smallSettings(uint32_t size) {
    PopulationSettings s;
    s.size = size;
    s.mutations = 4;
    s.radii = {2.0, 4.0, 12.0};
    return s;
}

TEST(PixelPopulation, ResamplingReplacesFortyPercentHalfFromEachSource) {
    Pcg32 rng(5);
    PixelPopulation population(smallSettings(1000), 40, 30, rng);
    PositionPool pool(40, 30);
    const auto positions = pool.next(1000, rng);
    PixelImportance empty;
    ResampleCounts c = population.resample(rng, positions, empty);
    EXPECT_EQ(c.eliminated, 400u);
    EXPECT_EQ(c.fromPool, 400u);  // no beta yet: all from the pool
    EXPECT_EQ(c.fromImportance, 0u);
    std::vector<RunningStats> pixels(40 * 30);
    for (auto& p : pixels) p.add(0.0), p.add(1.0);
    PixelImportance beta;
    beta.update(pixels, std::vector<double>(pixels.size(), 0.5));
    c = population.resample(rng, positions, beta);
    EXPECT_EQ(c.eliminated, 400u);
    EXPECT_EQ(c.fromPool, 200u);
    EXPECT_EQ(c.fromImportance, 200u);
    for (const auto& m : population.members()) {
        EXPECT_TRUE(m.pixel.x >= 0 && m.pixel.x < 40 && m.pixel.y >= 0 && m.pixel.y < 30);
        EXPECT_NEAR(m.alpha[0] + m.alpha[1] + m.alpha[2], 1.0, 1e-12);
    }
}

// Members regenerated from beta land within one pixel of a pixel drawn ∝ beta.
TEST(PixelPopulation, ImportanceReplacementsLandNearImportantPixels) {
    Pcg32 rng(9);
    PopulationSettings s = smallSettings(200);
    s.resampleRate = 1.0;
    PixelPopulation population(s, 20, 20, rng);
    std::vector<RunningStats> pixels(400);
    pixels[5 * 20 + 7].add(0.0), pixels[5 * 20 + 7].add(1.0);  // only pixel (7, 5) matters
    PixelImportance beta;
    beta.update(pixels, std::vector<double>(400, 0.5));
    PositionPool pool(20, 20);
    population.resample(rng, pool.next(200, rng), beta);
    // Replacements go in member order, the pool's first: members 100..199 come from beta.
    for (uint32_t i = 100; i < 200; ++i) {
        const glm::ivec2 p = population.members()[i].pixel;
        EXPECT_LE(std::abs(p.x - 7), 1);
        EXPECT_LE(std::abs(p.y - 5), 1);
    }
}

// Survivors are drawn with probability ∝ w = sigma^2 / N_used: with one survivor of two, the
// member of weight 3 survives against weight 2 3/5 of the time; members with w = 0 always go first.
TEST(PixelPopulation, SurvivalIsProportionalToTheEliminationWeight) {
    PopulationSettings s = smallSettings(2);
    s.resampleRate = 0.5;
    const PixelImportance empty;
    Pcg32 rng(13);
    int firstSurvived = 0;
    const int trials = 8000;
    for (int t = 0; t < trials; ++t) {
        PixelPopulation population(s, 16, 16, rng);
        // Member 0: variance 3, member 1: variance 2, both over one step (N_used = 1).
        population.record({0, 0, 0}, 0.0);
        population.record({0, 0, 0}, std::sqrt(6.0));
        population.record({0, 1, 1}, 0.0);
        population.record({0, 1, 1}, 2.0);
        population.endStep();
        const glm::ivec2 before = population.members()[0].pixel;
        std::vector<glm::dvec2> positions = {{15.5, 15.5}};
        population.resample(rng, positions, empty);
        if (population.members()[0].pixel == before) ++firstSurvived;
    }
    const double p = 3.0 / 5.0;
    const double sd = std::sqrt(p * (1 - p) / trials);
    EXPECT_NEAR(double(firstSurvived) / trials, p, 4.5 * sd);

    PopulationSettings s4 = smallSettings(4);
    s4.resampleRate = 0.5;
    PixelPopulation population(s4, 16, 16, rng);
    for (uint32_t i : {1u, 3u}) {
        population.record({0, i, 0}, 0.0);
        population.record({0, i, 0}, 1.0);
    }
    population.endStep();
    const auto before = population.members();
    population.resample(rng, {{15.5, 15.5}, {15.5, 15.5}}, empty);
    EXPECT_EQ(population.members()[1].pixel, before[1].pixel);
    EXPECT_EQ(population.members()[3].pixel, before[3].pixel);
    EXPECT_NE(population.members()[0].pixel, before[0].pixel);
    EXPECT_NE(population.members()[2].pixel, before[2].pixel);
}

// A step's draws follow their expected counts (the member-by-member sum over pixel disks in
// PixelPopulation::drawMutations's comment): many steps' draws per pixel pass a chi-square test.
TEST(PixelPopulation, StepDrawsFollowTheirExpectedCounts) {
    const int w = 24, h = 16;
    Pcg32 rng(17);
    PopulationSettings s = smallSettings(12);
    PixelPopulation population(s, w, h, rng);
    // Unequal alphas, as after adaptation.
    for (uint32_t i = 0; i < 12; ++i) {
        population.record({0, i, i % 3}, 0.0);
        population.record({0, i, i % 3}, 1.0 + i);
        population.record({0, i, (i + 1) % 3}, 0.0);
        population.record({0, i, (i + 1) % 3}, 0.5);
    }
    population.adapt();
    std::vector<double> q(size_t(w * h), 0.0);
    for (const auto& m : population.members())
        for (int k = 0; k < 3; ++k) {
            const auto disk = pixelDisk(m.pixel, s.radii[size_t(k)], w, h);
            for (const auto& p : disk)
                q[size_t(p.y * w + p.x)] += s.mutations * m.alpha[size_t(k)] / double(disk.size());
        }
    double total = 0.0;
    for (double v : q) total += v;
    EXPECT_NEAR(total, 12.0 * s.mutations, 1e-9);
    const int steps = 300;
    std::vector<double> observed(size_t(w * h), 0.0), expected(size_t(w * h), 0.0);
    for (int t = 0; t < steps; ++t) {
        std::vector<PositionDraw> out;
        population.drawMutations(rng, out);
        ASSERT_EQ(out.size(), 12u * s.mutations);
        for (const auto& d : out) observed[d.pixel] += 1.0;
    }
    for (size_t p = 0; p < q.size(); ++p) expected[p] = steps * q[p];
    const Chi2Result chi2 = chi2Test(observed, expected);
    EXPECT_GT(chi2.pValue, 0.001) << chi2.describe();
}

}  // namespace
}  // namespace pmcr::test
