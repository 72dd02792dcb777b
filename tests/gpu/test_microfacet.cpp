// shaders/common/microfacet.glsl: GGX D is normalised in projected area, visible-normal sampling
// draws the density ggxVisibleNormalPdf states (chi-square) and that density is normalised,
// Fresnel reflectance matches the Fresnel equations at known points from both sides, and
// refraction obeys Snell's law.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "distribution_test.h"
#include "gpu_test.h"

namespace pmcr::test {
namespace {

constexpr double kPi = std::numbers::pi;

struct MicrofacetPush {
    uint32_t mode;
    uint32_t count;
    uint32_t seed;
    float alpha;
    glm::vec3 wo;
};

enum MicrofacetMode : uint32_t { Eval = 0, SampleVisible, Fresnel, Refract };

// Alphas from roughness 0.05 (the sharpest rough lobe materials use) to 1.
constexpr float kAlphas[] = {0.0025f, 0.01f, 0.09f, 0.3f, 0.6f, 1.0f};

glm::vec3 woAt(double cosTheta) {
    return glm::vec3(float(std::sqrt(1.0 - cosTheta * cosTheta)), 0.0f, float(cosTheta));
}

class MicrofacetTest : public GpuTest {
protected:
    std::vector<glm::vec4> call(MicrofacetMode mode, uint32_t n, const std::vector<glm::vec4>& in,
                                float alpha = 0, glm::vec3 wo = glm::vec3(0, 0, 1),
                                uint32_t seed = 0) {
        auto inBuf = in.empty() ? zeros(16) : storage(in, "microfacet inputs");
        auto out = zeros(size_t(n) * 16, "microfacet results");
        run("tests/microfacet_test", MicrofacetPush{mode, n, seed, alpha, wo}, n, {&inBuf, &out});
        return out.download<glm::vec4>(n);
    }
    // Component `k` of the Eval results (0: D, 1: visible normal pdf) times m.z^zPower.
    DensityBatch evalDensity(float alpha, glm::vec3 wo, int k, int zPower) {
        return [=, this](const std::vector<glm::vec3>& ms) {
            std::vector<glm::vec4> in;
            in.reserve(ms.size());
            for (const glm::vec3& m : ms)
                in.push_back(glm::vec4(m, 0.0f));
            const auto r = call(Eval, uint32_t(ms.size()), in, alpha, wo);
            std::vector<double> v(ms.size());
            for (size_t i = 0; i < ms.size(); ++i)
                v[i] = double(r[i][k]) * (zPower ? double(ms[i].z) : 1.0);
            return v;
        };
    }
};

// Cells of the upper hemisphere graded towards the pole, where GGX concentrates for small alpha
// and where, for grazing wo, the support of D_wo (wo.m > 0) ends close by.
SphereGrid hemisphereGrid(float alpha, int zCells, int phiCells) {
    const double firstWidth = std::clamp(double(alpha) * alpha / 8.0, 1e-7, 1e-3);
    return SphereGrid(gradedBreaks(0.0, 1.0, 1.0, zCells, firstWidth),
                      uniformBreaks(0.0, 2 * kPi, phiCells));
}

TEST_F(MicrofacetTest, DistributionIsNormalisedInProjectedArea) {
    for (float alpha : kAlphas) {
        SCOPED_TRACE(alpha);
        const SphereGrid grid = hemisphereGrid(alpha, 48, 1);  // D is isotropic
        const CellIntegrals r = integrateCells(grid, evalDensity(alpha, glm::vec3(0, 0, 1), 0, 1),
                                               [](double v) { return 1e-5 * v + 1e-9; });
        EXPECT_NEAR(r.total(), 1.0, 2e-4 + r.error) << "integral of D(m) cos(theta_m)";
    }
}

TEST_F(MicrofacetTest, VisibleNormalSamplingFollowsItsPdf) {
    const uint32_t n = 1 << 17;
    uint32_t seed = 100;
    for (float alpha : {0.01f, 0.09f, 0.3f, 0.6f, 1.0f})
        for (double cosO : {1.0, 0.7, 0.2, 0.02}) {
            SCOPED_TRACE("alpha " + std::to_string(alpha) + " cos(theta_o) " +
                         std::to_string(cosO));
            const glm::vec3 wo = woAt(cosO);
            const SphereGrid grid = hemisphereGrid(alpha, 24, 32);
            const CellIntegrals expected =
                integrateCells(grid, evalDensity(alpha, wo, 1, 0), countTolerance(n));
            EXPECT_NEAR(expected.total(), 1.0, 1e-3 + expected.error) << "integral of D_wo";

            const auto s = call(SampleVisible, n, {}, alpha, wo, ++seed);
            std::vector<glm::dvec3> ms;
            for (const glm::vec4& m : s) {
                ASSERT_NEAR(glm::length(glm::vec3(m)), 1.0f, 1e-5f);
                ASSERT_GT(m.z, 0.0f);
                ms.push_back(glm::dvec3(glm::vec3(m)));
            }
            const auto exp = expectedCounts(grid, expected, n, ms, evalDensity(alpha, wo, 1, 0));
            EXPECT_TRUE(chi2Passes(grid.histogram(ms), exp,
                                   "ggxSampleVisibleNormal alpha " + std::to_string(alpha) +
                                       " cos " + std::to_string(cosO)));
        }
}

// Fresnel equations in their angle form (Born and Wolf sec. 1.5.2), unpolarised.
double fresnelReference(double cosI, double eta) {
    if (cosI < 0.0) {
        cosI = -cosI;
        eta = 1.0 / eta;
    }
    const double thetaI = std::acos(std::min(cosI, 1.0));
    const double sinT = std::sin(thetaI) / eta;
    if (sinT >= 1.0)
        return 1.0;
    const double thetaT = std::asin(sinT);
    if (thetaI < 1e-6)
        return std::pow((eta - 1) / (eta + 1), 2);
    const double rs = std::pow(std::sin(thetaI - thetaT) / std::sin(thetaI + thetaT), 2);
    const double rp = std::pow(std::tan(thetaI - thetaT) / std::tan(thetaI + thetaT), 2);
    return 0.5 * (rs + rp);
}

TEST_F(MicrofacetTest, FresnelMatchesTheFresnelEquations) {
    std::vector<glm::vec4> in;
    std::vector<double> expected;
    auto add = [&](double cosI, double eta, double value) {
        in.push_back(glm::vec4(float(cosI), float(eta), 0.0f, 0.0f));
        expected.push_back(value);
    };
    for (double eta : {1.0, 1.33, 1.5, 2.4}) {
        add(1.0, eta, std::pow((eta - 1) / (eta + 1), 2));  // normal incidence
        add(-1.0, eta, std::pow((eta - 1) / (eta + 1), 2));
        // Brewster's angle tan(theta_B) = eta: R_p = 0, R_s = cos^2(2 theta_B).
        const double thetaB = std::atan(eta);
        add(std::cos(thetaB), eta, 0.5 * std::pow(std::cos(2 * thetaB), 2));
        // From inside, past the critical angle asin(1 / eta): total internal reflection.
        if (eta > 1.0) {
            const double critical = std::asin(1.0 / eta);
            add(-std::cos(critical + 0.01), eta, 1.0);
            add(std::cos(critical + 0.01), 1.0 / eta, 1.0);
        }
        for (int k = 0; k <= 40; ++k) {
            const double c = -1.0 + 2.0 * k / 40.0;
            add(c, eta, fresnelReference(c, eta));
        }
    }
    const uint32_t n = uint32_t(in.size());
    const auto r = call(Fresnel, n, in);
    for (uint32_t i = 0; i < n; ++i)
        ASSERT_NEAR(r[i].x, expected[i], 2e-5) << "cos " << in[i].x << " eta " << in[i].y;

    // Both sides: light refracted into the medium sees the same transmittance coming back.
    in.clear();
    std::vector<glm::vec4> back;
    for (double eta : {1.33, 1.5, 2.4})
        for (int k = 1; k <= 20; ++k) {
            const double cosI = k / 20.0;
            const double sinT = std::sqrt(1 - cosI * cosI) / eta;
            in.push_back(glm::vec4(float(cosI), float(eta), 0.0f, 0.0f));
            back.push_back(glm::vec4(float(-std::sqrt(1 - sinT * sinT)), float(eta), 0.0f, 0.0f));
        }
    const auto front = call(Fresnel, uint32_t(in.size()), in);
    const auto inside = call(Fresnel, uint32_t(back.size()), back);
    for (size_t i = 0; i < in.size(); ++i)
        EXPECT_NEAR(front[i].x, inside[i].x, 2e-5) << "cos " << in[i].x << " eta " << in[i].y;

    // Schlick: F0 at normal incidence, 1 at grazing, F0 + (1 - F0) / 32 at cos = 1/2.
    const auto schlick = call(
        Fresnel, 3, {{1.0f, 1.5f, 0.3f, 0.0f}, {0.0f, 1.5f, 0.3f, 0.0f}, {0.5f, 1.5f, 0.3f, 0.0f}});
    EXPECT_NEAR(schlick[0].y, 0.3f, 1e-6f);
    EXPECT_NEAR(schlick[1].y, 1.0f, 1e-6f);
    EXPECT_NEAR(schlick[2].y, 0.3f + 0.7f / 32.0f, 1e-6f);
}

TEST_F(MicrofacetTest, RefractionObeysSnellsLaw) {
    std::mt19937 gen(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    auto randomUnit = [&] {
        const double z = 1 - 2 * u(gen), phi = 2 * kPi * u(gen);
        return directionFromZPhi(z, phi);
    };
    std::vector<glm::vec4> in;
    std::vector<glm::dvec3> ws, ns;
    std::vector<double> etas;
    for (int i = 0; i < 4096; ++i) {
        const glm::dvec3 n = randomUnit();
        glm::dvec3 w = randomUnit();
        if (glm::dot(w, n) < 0)
            w = -w;
        const double eta = std::array<double, 4>{1.5, 1 / 1.5, 1.33, 2.4}[size_t(i % 4)];
        in.push_back(glm::vec4(glm::vec3(w), float(eta)));
        in.push_back(glm::vec4(glm::vec3(n), 0.0f));
        ws.push_back(w);
        ns.push_back(n);
        etas.push_back(eta);
    }
    const uint32_t count = uint32_t(ws.size());
    const auto r = call(Refract, count, in);
    std::vector<glm::vec4> reverse;
    for (uint32_t i = 0; i < count; ++i) {
        const glm::dvec3 w = ws[i], n = ns[i];
        const double cosI = glm::dot(w, n), sin2I = 1 - cosI * cosI;
        const bool tir = sin2I / (etas[i] * etas[i]) >= 1.0;
        if (std::abs(sin2I / (etas[i] * etas[i]) - 1.0) < 1e-4)
            continue;  // too close to call
        ASSERT_EQ(r[i].w == 0.0f, tir) << "total internal reflection iff sin^2 > eta^2, " << i;
        if (tir) {
            reverse.push_back(glm::vec4(0, 0, 1, 1));
            reverse.push_back(glm::vec4(0, 0, 1, 0));
            continue;
        }
        const glm::dvec3 wt = glm::dvec3(glm::vec3(r[i]));
        ASSERT_NEAR(glm::length(wt), 1.0, 1e-5);
        ASSERT_LT(glm::dot(wt, n), 0.0) << "transmitted to the other side";
        // Snell: sin(theta_i) = eta sin(theta_t); in the plane of w and n, tangents opposite.
        ASSERT_NEAR(std::sqrt(sin2I), etas[i] * glm::length(glm::cross(wt, n)), 1e-5);
        ASSERT_NEAR(glm::dot(wt, glm::cross(n, w)), 0.0, 1e-5);
        ASSERT_LE(glm::dot(wt - glm::dot(wt, n) * n, w - cosI * n), 1e-6);
        reverse.push_back(glm::vec4(r[i].x, r[i].y, r[i].z, float(1.0 / etas[i])));
        reverse.push_back(glm::vec4(glm::vec3(-n), 0.0f));
    }
    // Reversibility: refracting wt back through -n with 1 / eta gives w.
    const auto back = call(Refract, uint32_t(reverse.size() / 2), reverse);
    for (size_t i = 0, j = 0; i < count; ++i) {
        const double sin2I = 1 - std::pow(glm::dot(ws[i], ns[i]), 2);
        if (std::abs(sin2I / (etas[i] * etas[i]) - 1.0) < 1e-4)
            continue;
        if (r[i].w != 0.0f) {
            ASSERT_NE(back[j].w, 0.0f);
            ASSERT_NEAR(glm::length(glm::dvec3(glm::vec3(back[j])) - ws[i]), 0.0, 1e-3) << i;
        }
        ++j;
    }
}

}  // namespace
}  // namespace pmcr::test
