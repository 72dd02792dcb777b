// The warps of shaders/common/sampling.glsl: samples land in their domain, their histogram over
// equal-area or graded cells matches the documented density integrated per cell (chi-square),
// and the density functions the kernels use integrate to 1. Its MIS heuristics (power, and
// balance for --mis balance) give weights that sum to 1 over a light and a BSDF sample.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "distribution_test.h"
#include "gpu_test.h"

namespace pmcr::test {
namespace {

constexpr double kPi = std::numbers::pi;

struct WarpPush {
    uint32_t mode;
    uint32_t count;
    uint32_t seed;
    float cosThetaMax;
};

enum WarpMode : uint32_t {
    Disk = 0, CosineHemisphere, UniformSphere, UniformCone, Triangle, Pdf, MisWeights
};

class WarpTest : public GpuTest {
protected:
    std::vector<glm::vec4> sample(WarpMode mode, uint32_t n, uint32_t seed, float cosThetaMax = 0) {
        auto unused = zeros(16);
        auto out = zeros(size_t(n) * 16, "warp samples");
        run("tests/warp_test", WarpPush{mode, n, seed, cosThetaMax}, n, {&unused, &out});
        return out.download<glm::vec4>(n);
    }
    // (cosineHemispherePdf(w.z), uniformConePdf(cosThetaMax)) at each direction.
    std::vector<glm::vec4> densities(const std::vector<glm::vec3>& dirs, float cosThetaMax = 0) {
        std::vector<glm::vec4> in;
        in.reserve(dirs.size());
        for (const glm::vec3& w : dirs)
            in.push_back(glm::vec4(w, 0.0f));
        auto inBuf = storage(in, "warp directions");
        auto out = zeros(in.size() * 16, "warp densities");
        const uint32_t n = uint32_t(in.size());
        run("tests/warp_test", WarpPush{Pdf, n, 0, cosThetaMax}, n, {&inBuf, &out});
        return out.download<glm::vec4>(n);
    }
    DensityBatch cosinePdf() {
        return [this](const std::vector<glm::vec3>& dirs) {
            const auto d = densities(dirs);
            std::vector<double> v(d.size());
            for (size_t i = 0; i < d.size(); ++i)
                v[i] = d[i].x;
            return v;
        };
    }
};

std::vector<glm::dvec3> directions(const std::vector<glm::vec4>& samples) {
    std::vector<glm::dvec3> dirs;
    dirs.reserve(samples.size());
    for (const glm::vec4& s : samples)
        dirs.push_back(glm::dvec3(glm::vec3(s)));
    return dirs;
}

TEST_F(WarpTest, ConcentricDiskIsUniform) {
    const uint32_t n = 1 << 20;
    const auto s = sample(Disk, n, 1);
    // Equal-area cells: r^2 and phi uniform.
    const int nr = 32, nphi = 64;
    std::vector<double> counts(nr * nphi, 0.0);
    for (const glm::vec4& p : s) {
        const double r2 = double(p.x) * p.x + double(p.y) * p.y;
        ASSERT_LE(r2, 1.0 + 1e-6);
        double phi = std::atan2(double(p.y), double(p.x));
        if (phi < 0.0)
            phi += 2.0 * kPi;
        const int i = std::min(int(r2 * nr), nr - 1),
                  j = std::min(int(phi / (2 * kPi) * nphi), nphi - 1);
        counts[size_t(i * nphi + j)] += 1.0;
    }
    EXPECT_TRUE(chi2Passes(counts, std::vector<double>(nr * nphi, double(n) / (nr * nphi)),
                           "sampleUniformDiskConcentric"));
}

TEST_F(WarpTest, CosineHemisphereFollowsItsPdf) {
    const uint32_t n = 1 << 20;
    const auto s = sample(CosineHemisphere, n, 2);
    for (const glm::vec4& w : s) {
        ASSERT_NEAR(glm::length(glm::vec3(w)), 1.0f, 1e-5f);
        ASSERT_GE(w.z, 0.0f);
        ASSERT_NEAR(w.w, w.z / kPi, 1e-6) << "cosineHemispherePdf(z) = z / pi";
    }
    const SphereGrid grid(uniformBreaks(0, 1, 32), uniformBreaks(0, 2 * kPi, 64));
    const CellIntegrals expected = integrateCells(grid, cosinePdf(), countTolerance(n));
    // The quadrature against the closed form (z1^2 - z0^2) / 2 * dphi / pi per cell.
    for (int c = 0; c < grid.cellCount(); ++c) {
        double z0, z1, p0, p1;
        grid.bounds(c, z0, z1, p0, p1);
        ASSERT_NEAR(expected.value[size_t(c)], (z1 * z1 - z0 * z0) / 2 * (p1 - p0) / kPi, 1e-6);
    }
    std::vector<double> counts = grid.histogram(directions(s));
    std::vector<double> exp(expected.value);
    for (double& e : exp)
        e *= n;
    EXPECT_TRUE(chi2Passes(counts, exp, "sampleCosineHemisphere"));
}

TEST_F(WarpTest, CosineHemispherePdfIntegratesToOne) {
    const SphereGrid grid(uniformBreaks(-1, 1, 16), uniformBreaks(0, 2 * kPi, 8));
    const CellIntegrals r = integrateCells(grid, cosinePdf(), [](double) { return 1e-7; });
    EXPECT_NEAR(r.total(), 1.0, 1e-5 + r.error);
}

TEST_F(WarpTest, UniformSphereIsUniform) {
    const uint32_t n = 1 << 20;
    const auto s = sample(UniformSphere, n, 3);
    for (const glm::vec4& w : s)
        ASSERT_NEAR(glm::length(glm::vec3(w)), 1.0f, 1e-5f);
    const SphereGrid grid(uniformBreaks(-1, 1, 32), uniformBreaks(0, 2 * kPi, 64));
    EXPECT_TRUE(
        chi2Passes(grid.histogram(directions(s)),
                   std::vector<double>(size_t(grid.cellCount()), double(n) / grid.cellCount()),
                   "sampleUniformSphere"));
}

TEST_F(WarpTest, UniformConeFollowsItsPdf) {
    const uint32_t n = 1 << 18;
    uint32_t seed = 40;
    for (float cosMax : {0.999f, 0.9f, 0.2f, -0.6f}) {
        SCOPED_TRACE(cosMax);
        const auto s = sample(UniformCone, n, ++seed, cosMax);
        const double pdf = s[0].w;
        // The density is 1 / solid angle of the cone.
        EXPECT_NEAR(pdf * 2 * kPi * (1 - double(cosMax)), 1.0, 1e-4);
        for (const glm::vec4& w : s) {
            ASSERT_NEAR(glm::length(glm::vec3(w)), 1.0f, 1e-5f);
            ASSERT_GE(w.z, cosMax - 1e-6f);
        }
        const SphereGrid grid(uniformBreaks(cosMax, 1, 16), uniformBreaks(0, 2 * kPi, 32));
        std::vector<double> exp(size_t(grid.cellCount()));
        for (int c = 0; c < grid.cellCount(); ++c) {
            double z0, z1, p0, p1;
            grid.bounds(c, z0, z1, p0, p1);
            exp[size_t(c)] = n * pdf * (z1 - z0) * (p1 - p0);
        }
        double outside = 0.0;
        const auto counts = grid.histogram(directions(s), &outside);
        EXPECT_EQ(outside, 0.0);
        EXPECT_TRUE(chi2Passes(counts, exp, "sampleUniformCone " + std::to_string(cosMax)));
    }
}

TEST_F(WarpTest, TriangleIsUniform) {
    const uint32_t n = 1 << 20;
    const auto s = sample(Triangle, n, 5);
    const int cells = 16;
    std::vector<double> counts(cells * cells, 0.0);
    for (const glm::vec4& b : s) {
        ASSERT_GE(b.x, 0.0f);
        ASSERT_GE(b.y, 0.0f);
        ASSERT_LE(double(b.x) + b.y, 1.0 + 1e-6);
        counts[barycentricCell(b.x, b.y, cells)] += 1.0;
    }
    std::vector<double> exp = barycentricCellAreas(cells);
    for (double& e : exp)
        e *= n;
    EXPECT_TRUE(chi2Passes(counts, exp, "sampleUniformTriangle"));
}

// The MIS weights of a light sample and a BSDF sample (path_tracer.glsl's misWeight): for each
// heuristic, the weight of strategy A against B plus that of B against A is 1 wherever either
// density is positive, with one sample of each (pt) or n of each (direct) or unequal counts, at
// densities from 1e-6 to 1e6, one of them zero, or infinite (a delta: weight 1); and each
// weight equals Veach's formula (1997, eqs. 9.8 and 9.13).
TEST_F(WarpTest, MisWeightsOfAPairSumToOne) {
    const float inf = std::numeric_limits<float>::infinity();
    std::vector<glm::vec4> cases;  // (pdf A, pdf B, count A, count B)
    std::mt19937 gen(17);
    std::uniform_real_distribution<float> logPdf(-6.0f, 6.0f);
    const glm::vec2 counts[] = {{1, 1}, {2, 2}, {8, 8}, {1, 4}, {3, 1}};
    for (int i = 0; i < 4096; ++i) {
        const glm::vec2 n = counts[i % 5];
        cases.push_back({std::pow(10.0f, logPdf(gen)), std::pow(10.0f, logPdf(gen)), n.x, n.y});
    }
    for (float pdf : {1e-6f, 0.3f, 1e6f}) {
        cases.push_back({pdf, 0.0f, 1.0f, 1.0f});
        cases.push_back({0.0f, pdf, 2.0f, 2.0f});
        cases.push_back({inf, pdf, 1.0f, 1.0f});
        cases.push_back({pdf, inf, 1.0f, 1.0f});
    }
    auto in = storage(cases, "mis pdfs");
    auto out = zeros(cases.size() * 16, "mis weights");
    const uint32_t n = uint32_t(cases.size());
    run("tests/warp_test", WarpPush{MisWeights, n, 0, 0.0f}, n, {&in, &out});
    const auto w = out.download<glm::vec4>(n);
    for (uint32_t i = 0; i < n; ++i) {
        const glm::vec4 c = cases[i];
        SCOPED_TRACE("pdfs " + std::to_string(c.x) + ", " + std::to_string(c.y) + ", counts " +
                     std::to_string(c.z) + ", " + std::to_string(c.w));
        ASSERT_NEAR(w[i].x + w[i].y, 1.0f, 1e-5f) << "power heuristic";
        ASSERT_NEAR(w[i].z + w[i].w, 1.0f, 1e-5f) << "balance heuristic";
        if (std::isinf(c.x) || std::isinf(c.y)) {
            ASSERT_EQ(w[i].x, std::isinf(c.x) ? 1.0f : 0.0f);
            ASSERT_EQ(w[i].z, std::isinf(c.x) ? 1.0f : 0.0f);
            continue;
        }
        const double a = double(c.z) * c.x, b = double(c.w) * c.y;
        ASSERT_NEAR(w[i].x, a * a / (a * a + b * b), 1e-5) << "power heuristic";
        ASSERT_NEAR(w[i].z, a / (a + b), 1e-5) << "balance heuristic";
    }
}

}  // namespace
}  // namespace pmcr::test
