// PSSMLT's mutations (shaders/methods/pssmlt/pss_mutation.glsl, pss_sampler.glsl), run by the
// renderer's own lazy sampler:
//  - a small step's proposals follow their density, the Gaussian of sigma wrapped around [0, 1)
//    (chi-square, from a start near 0 so that a good share wraps);
//  - n small steps composed lazily in one and n successive accepted small steps both follow the
//    wrapped Gaussian of sigma sqrt(n);
//  - a large step, and a coordinate read after a large step it missed, are uniform;
//  - detailed balance: the transition density is symmetric, T(x -> y) = T(y -> x), checked
//    empirically by counting proposals from x that land near y and from y that land near x,
//    across the wrap-around and away from it (each count also against the density);
//  - a rejection restores the coordinate and the iteration exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "distribution_test.h"
#include "gpu_test.h"
#include "shared/host_device.h"

namespace pmcr::test {
namespace {

struct MutationPush {
    uint32_t mode;
    uint32_t count;
    uint32_t seed;
    uint32_t n;
    float x;
    float sigma;
};

constexpr uint32_t kSamples = 1u << 18;
constexpr int kCells = 64;

double normalCdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

// Mass of [a, b) under the Gaussian of `sigma` around x wrapped around [0, 1).
double wrappedGaussianMass(double x, double sigma, double a, double b) {
    double mass = 0.0;
    const int k = int(std::ceil(8.0 * sigma)) + 1;
    for (int j = -k; j <= k; ++j)
        mass += normalCdf((b - x + j) / sigma) - normalCdf((a - x + j) / sigma);
    return mass;
}

std::vector<double> histogram(const std::vector<float>& values, int cells) {
    std::vector<double> counts(cells, 0.0);
    for (float v : values) counts[std::min(cells - 1, int(double(v) * cells))] += 1.0;
    return counts;
}

std::vector<double> wrappedGaussianCounts(double x, double sigma, int cells, double n) {
    std::vector<double> expected(cells);
    for (int c = 0; c < cells; ++c)
        expected[c] = n * wrappedGaussianMass(x, sigma, double(c) / cells, double(c + 1) / cells);
    return expected;
}

class PssmltMutation : public GpuTest {
protected:
    std::vector<float> draw(uint32_t mode, float x, float sigma, uint32_t n, uint32_t seed,
                            uint32_t count = kSamples) {
        const size_t floats = size_t(count) * (mode == 3 ? 4 : 1);
        auto out = zeros(floats * 4, "mutation results");
        auto primary = zeros(size_t(count) * sizeof(gpu::PrimarySample), "primary samples");
        run("tests/pssmlt_mutation_test", MutationPush{mode, count, seed, n, x, sigma}, count,
            {&out, nullptr, nullptr, &primary});
        return out.download<float>(floats);
    }
};

TEST_F(PssmltMutation, ValuesStayInTheUnitInterval) {
    for (uint32_t mode : {0u, 1u, 2u, 4u})
        for (float x : {0.0f, 0.5f, 0.99999994f})
            for (float v : draw(mode, x, 0.3f, 3, 5 + mode, 1u << 14)) {
                ASSERT_GE(v, 0.0f) << "mode " << mode;
                ASSERT_LT(v, 1.0f) << "mode " << mode;
            }
}

TEST_F(PssmltMutation, SmallStepFollowsTheWrappedGaussian) {
    const float x = 0.02f, sigma = 0.1f;
    const auto y = draw(0, x, sigma, 1, 11);
    EXPECT_TRUE(chi2Passes(histogram(y, kCells), wrappedGaussianCounts(x, sigma, kCells, kSamples),
                           "pssmlt small step, sigma 0.1 from 0.02"));
}

TEST_F(PssmltMutation, LazyCompositionMatchesSuccessiveSteps) {
    const float x = 0.97f, sigma = 0.05f;
    const uint32_t n = 4;
    const auto expected = wrappedGaussianCounts(x, sigma * std::sqrt(double(n)), kCells, kSamples);
    EXPECT_TRUE(chi2Passes(histogram(draw(0, x, sigma, n, 12), kCells), expected,
                           "pssmlt 4 small steps composed lazily"));
    EXPECT_TRUE(chi2Passes(histogram(draw(1, x, sigma, n, 13), kCells), expected,
                           "pssmlt 4 successive small steps"));
}

TEST_F(PssmltMutation, LargeStepsAreUniform) {
    const std::vector<double> uniform(kCells, double(kSamples) / kCells);
    EXPECT_TRUE(chi2Passes(histogram(draw(2, 0.3f, 0.01f, 1, 14), kCells), uniform,
                           "pssmlt large step"));
    EXPECT_TRUE(chi2Passes(histogram(draw(4, 0.3f, 0.01f, 7, 15), kCells), uniform,
                           "pssmlt read after a missed large step"));
}

// T(x -> y) and T(y -> x) estimated as the share of proposals from x within h of y and from y
// within h of x: equal, and equal to the density's mass there.
void expectSymmetric(const std::vector<float>& fromX, const std::vector<float>& fromY, double x,
                     double y, double sigma, double h) {
    auto near = [h](const std::vector<float>& v, double centre) {
        double count = 0.0;
        for (float u : v) {
            double d = std::abs(double(u) - centre);
            d = std::min(d, 1.0 - d);  // distance on the circle
            if (d < h) count += 1.0;
        }
        return count;
    };
    const double xy = near(fromX, y), yx = near(fromY, x);
    const double expected = double(fromX.size()) * wrappedGaussianMass(x, sigma, y - h, y + h);
    EXPECT_GT(xy, 1000.0);
    EXPECT_LT(std::abs(xy - yx), 4.5 * std::sqrt(xy + yx))
        << "T(x -> y) count " << xy << ", T(y -> x) count " << yx << " (x " << x << ", y " << y << ")";
    EXPECT_LT(std::abs(xy - expected), 4.5 * std::sqrt(expected)) << "x -> y, expected " << expected;
    EXPECT_LT(std::abs(yx - expected), 4.5 * std::sqrt(expected)) << "y -> x, expected " << expected;
}

TEST_F(PssmltMutation, TransitionDensityIsSymmetric) {
    const float sigma = 0.05f;
    // Across the wrap-around: 0.01 and 0.97 are 0.04 apart on the circle.
    expectSymmetric(draw(0, 0.01f, sigma, 1, 21), draw(0, 0.97f, sigma, 1, 22), 0.01, 0.97, sigma, 0.005);
    // Away from it.
    expectSymmetric(draw(0, 0.3f, sigma, 1, 23), draw(0, 0.37f, sigma, 1, 24), 0.3, 0.37, sigma, 0.005);
    // Composed steps (sigma sqrt(3)) across the wrap-around.
    expectSymmetric(draw(0, 0.95f, sigma, 3, 25), draw(0, 0.05f, sigma, 3, 26), 0.95, 0.05,
                    sigma * std::sqrt(3.0), 0.005);
}

TEST_F(PssmltMutation, RejectionRestoresTheCoordinate) {
    const float x = 0.123456f;
    const auto r = draw(3, x, 0.01f, 1, 31, 4096);
    int moved = 0;
    for (size_t i = 0; i < 4096; ++i) {
        if (r[4 * i] != x) ++moved;
        ASSERT_EQ(r[4 * i + 1], x) << "value after rejection";
        ASSERT_EQ(r[4 * i + 2], 0.0f) << "last modification after rejection";
        ASSERT_EQ(r[4 * i + 3], 0.0f) << "iteration after rejection";
    }
    EXPECT_GT(moved, 4000) << "the proposals moved";
}

}  // namespace
}  // namespace pmcr::test
