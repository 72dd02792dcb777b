// Emitter power, the Walker alias table the kernels sample, and scene finalisation.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <glm/gtc/constants.hpp>

#include "core/error.h"
#include "scene/scene.h"
#include "scene_builder.h"

namespace pmcr {
namespace {

using test::addTriangle;
using test::testMaterial;

// Right triangles in the z = 0 plane with legs `a` (area a^2 / 2), placed along x.
Scene sceneWithEmitters(const std::vector<float>& legs, const std::vector<glm::vec3>& emission,
                        const std::vector<bool>& doubleSided) {
    Scene s;
    s.path = "emitters.gltf";
    s.materials.push_back(testMaterial(glm::vec3(0.0f)));  // a non-emissive floor
    addTriangle(s, {0, -1, 0}, {10, -1, 0}, {0, -1, 10}, 0);
    for (size_t i = 0; i < legs.size(); ++i) {
        s.materials.push_back(testMaterial(emission[i], doubleSided[i]));
        const glm::vec3 o(float(i) * 3.0f, 0.0f, 0.0f);
        addTriangle(s, o, o + glm::vec3(legs[i], 0, 0), o + glm::vec3(0, legs[i], 0),
                    uint32_t(s.materials.size() - 1));
    }
    return s;
}

// Regularized upper incomplete gamma Q(a, x): power series for x < a + 1, else Legendre's
// continued fraction evaluated with the modified Lentz method (Abramowitz & Stegun 6.5).
double gammaQ(double a, double x) {
    if (x <= 0.0)
        return 1.0;
    const double logPrefix = a * std::log(x) - x - std::lgamma(a);
    if (x < a + 1.0) {
        double term = 1.0 / a, sum = term;
        for (int n = 1; n < 10000 && std::abs(term) > 1e-15 * std::abs(sum); ++n) {
            term *= x / (a + n);
            sum += term;
        }
        return 1.0 - sum * std::exp(logPrefix);
    }
    const double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 10000; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        d = std::abs(d) < tiny ? tiny : d;
        c = b + an / c;
        c = std::abs(c) < tiny ? tiny : c;
        d = 1.0 / d;
        const double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1.0) < 1e-15)
            break;
    }
    return std::exp(logPrefix) * h;
}

// The kernels' selection rule (shaders/shared/scene_types.h, Emitter): slot = min(floor(u n),
// n - 1), kept when u2 < aliasThreshold, else its alias. Uniforms are 24-bit floats in [0, 1).
std::vector<double> sampleCounts(const EmitterTable& table, size_t samples, uint32_t seed) {
    std::mt19937 rng(seed);
    auto uniform = [&] { return float(rng() >> 8) * 0x1p-24f; };
    const uint32_t n = uint32_t(table.emitters.size());
    std::vector<double> counts(n, 0.0);
    for (size_t k = 0; k < samples; ++k) {
        const float u1 = uniform(), u2 = uniform();
        const uint32_t slot = std::min(uint32_t(u1 * float(n)), n - 1);
        const gpu::Emitter& e = table.emitters[slot];
        counts[u2 < e.aliasThreshold ? slot : e.alias] += 1.0;
    }
    return counts;
}

// Pearson's chi-square p-value of `counts` against `pmf`, cells with expected count below 5
// pooled (as pbrt-v4's chi2test does).
double chiSquarePValue(const std::vector<double>& counts, const std::vector<double>& pmf,
                       double samples) {
    double chi2 = 0.0, pooledObserved = 0.0, pooledExpected = 0.0;
    int cells = 0;
    for (size_t i = 0; i < counts.size(); ++i) {
        const double expected = pmf[i] * samples;
        if (expected < 5.0) {
            pooledObserved += counts[i];
            pooledExpected += expected;
            continue;
        }
        chi2 += (counts[i] - expected) * (counts[i] - expected) / expected;
        ++cells;
    }
    if (pooledExpected > 0.0) {
        chi2 += (pooledObserved - pooledExpected) * (pooledObserved - pooledExpected) /
                std::max(pooledExpected, 1e-12);
        ++cells;
    }
    return gammaQ(0.5 * (cells - 1), 0.5 * chi2);
}

std::vector<double> pmfOf(const EmitterTable& table) {
    std::vector<double> pmf;
    for (const gpu::Emitter& e : table.emitters)
        pmf.push_back(e.pmf);
    return pmf;
}

TEST(Emitters, ChiSquareTailMatchesTables) {
    // Upper tail of the chi-square distribution: Q(dof / 2, chi2 / 2).
    EXPECT_NEAR(gammaQ(1.0, 4.605170 / 2), 0.10, 1e-6);    // dof 2: exp(-chi2 / 2)
    EXPECT_NEAR(gammaQ(5.0, 23.209251 / 2), 0.01, 1e-6);   // dof 10, 1% critical value
    EXPECT_NEAR(gammaQ(31.5, 90.0 / 2), 0.0144145, 1e-6);  // dof 63 (continued fraction)
}

TEST(Emitters, LuminanceUsesRec709Weights) {
    EXPECT_FLOAT_EQ(luminance({1, 0, 0}), 0.2126f);
    EXPECT_FLOAT_EQ(luminance({0, 1, 0}), 0.7152f);
    EXPECT_FLOAT_EQ(luminance({0, 0, 1}), 0.0722f);
    EXPECT_NEAR(luminance({1, 1, 1}), 1.0f, 1e-6f);
}

TEST(Emitters, PowerIsAreaTimesLuminanceTimesPiPerSide) {
    const Scene s = sceneWithEmitters({2.0f, 2.0f}, {{1, 2, 3}, {1, 2, 3}}, {false, true});
    const float lum = 0.2126f + 0.7152f * 2.0f + 0.0722f * 3.0f;
    // Legs 2: area 2.
    EXPECT_NEAR(emitterPower(s, 1), 2.0f * lum * glm::pi<float>(), 1e-5f);
    EXPECT_NEAR(emitterPower(s, 2), 2.0f * 2.0f * lum * glm::pi<float>(), 1e-5f);
    EXPECT_EQ(emitterPower(s, 0), 0.0f);
}

TEST(Emitters, TableCoversEmissiveTrianglesWithPowerProportionalPmf) {
    const Scene s = sceneWithEmitters({1.0f, 2.0f, 0.5f}, {{1, 1, 1}, {0, 0, 0}, {4, 0, 0}},
                                      {false, false, true});
    const EmitterTable table = buildEmitters(s);
    ASSERT_EQ(table.emitters.size(), 2u);  // the floor and the black triangle emit nothing
    EXPECT_EQ(table.emitters[0].triangle, 1u);
    EXPECT_EQ(table.emitters[1].triangle, 3u);
    const double p1 = emitterPower(s, 1), p3 = emitterPower(s, 3);
    EXPECT_NEAR(table.totalPower, p1 + p3, 1e-5);
    EXPECT_NEAR(table.emitters[0].pmf, p1 / (p1 + p3), 1e-6);
    EXPECT_NEAR(table.emitters[1].pmf, p3 / (p1 + p3), 1e-6);
}

// Deterministic check: the table's selection probability of emitter i,
// (threshold_i + sum over slots j aliasing to i of (1 - threshold_j)) / n, is its pmf.
TEST(Emitters, AliasTableReproducesThePmfExactly) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> leg(0.01f, 3.0f), radiance(0.0f, 10.0f);
    std::vector<float> legs;
    std::vector<glm::vec3> emission;
    std::vector<bool> sides;
    for (int i = 0; i < 200; ++i) {
        legs.push_back(leg(rng));
        emission.emplace_back(radiance(rng), radiance(rng), radiance(rng));
        sides.push_back(i % 3 == 0);
    }
    const EmitterTable table = buildEmitters(sceneWithEmitters(legs, emission, sides));
    const size_t n = table.emitters.size();
    ASSERT_EQ(n, 200u);
    std::vector<double> probability(n, 0.0);
    double pmfSum = 0.0;
    for (size_t j = 0; j < n; ++j) {
        const gpu::Emitter& e = table.emitters[j];
        ASSERT_GE(e.aliasThreshold, 0.0f);
        ASSERT_LE(e.aliasThreshold, 1.0f);
        ASSERT_LT(e.alias, n);
        probability[j] += e.aliasThreshold / double(n);
        probability[e.alias] += (1.0 - e.aliasThreshold) / double(n);
        pmfSum += e.pmf;
    }
    EXPECT_NEAR(pmfSum, 1.0, 1e-5);
    for (size_t i = 0; i < n; ++i)
        EXPECT_NEAR(probability[i], table.emitters[i].pmf, 1e-6);
}

// 1e6 samples through the GPU rule against the pmf, for several tables, each at the Sidak-
// corrected 1% level.
TEST(Emitters, SampledFrequenciesMatchThePmfChiSquare) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> logLeg(-2.0f, 1.0f);
    std::vector<float> wideLegs;
    std::vector<glm::vec3> wideEmission;
    std::vector<bool> wideSides;
    for (int i = 0; i < 64; ++i) {
        wideLegs.push_back(std::pow(10.0f, logLeg(rng)));  // powers over six decades
        wideEmission.emplace_back(1.0f, 0.5f + 0.01f * float(i), 0.2f);
        wideSides.push_back(i % 2 == 0);
    }
    const std::vector<Scene> scenes = {
        sceneWithEmitters(wideLegs, wideEmission, wideSides),
        sceneWithEmitters({1.0f, 0.03f, 0.5f}, {{1, 1, 1}, {1, 1, 1}, {0.1f, 0.1f, 0.1f}},
                          {false, true, false}),
        sceneWithEmitters({1.0f, 1.0f, 1.0f, 1.0f, 1.0f},
                          {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}, {1, 1, 1}, {1, 1, 1}},
                          {false, false, false, false, false}),
    };
    const double alpha = 1.0 - std::pow(1.0 - 0.01, 1.0 / double(scenes.size()));
    const size_t samples = 1000000;
    for (size_t k = 0; k < scenes.size(); ++k) {
        const EmitterTable table = buildEmitters(scenes[k]);
        const std::vector<double> counts = sampleCounts(table, samples, 100 + uint32_t(k));
        const double p = chiSquarePValue(counts, pmfOf(table), double(samples));
        EXPECT_GT(p, alpha) << "table " << k;
    }
}

// The chi-square test has power: a table that ignores the aliases (uniform selection) fails.
TEST(Emitters, ChiSquareRejectsAWrongTable) {
    EmitterTable table = buildEmitters(sceneWithEmitters(
        {1.0f, 0.5f, 0.25f}, {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}}, {false, false, false}));
    for (gpu::Emitter& e : table.emitters)
        e.aliasThreshold = 1.0f;
    const std::vector<double> counts = sampleCounts(table, 1000000, 5);
    EXPECT_LT(chiSquarePValue(counts, pmfOf(table), 1e6), 1e-6);
}

TEST(FinalizeScene, ComputesBoundsAndDropsZeroAreaTriangles) {
    Scene s = sceneWithEmitters({1.0f}, {{1, 1, 1}}, {false});
    addTriangle(s, {0, 0, 0}, {1, 1, 1}, {2, 2, 2}, 0);     // collinear
    addTriangle(s, {50, 0, 0}, {50, 0, 0}, {50, 0, 0}, 0);  // a point: must not grow bounds
    testing::internal::CaptureStderr();
    finalizeScene(s);
    const std::string warnings = testing::internal::GetCapturedStderr();
    EXPECT_EQ(s.triangles.size(), 2u);
    EXPECT_NE(warnings.find("emitters.gltf: dropped 2 of 4 triangles with zero area"),
              std::string::npos)
        << warnings;
    EXPECT_EQ(s.boundsMin, glm::vec3(0, -1, 0));
    EXPECT_EQ(s.boundsMax, glm::vec3(10, 1, 10));
}

void expectFinalizeError(Scene s, const std::string& problem) {
    try {
        finalizeScene(s);
        ADD_FAILURE() << "no error; expected '" << problem << "'";
    } catch (const Error& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.rfind("emitters.gltf: ", 0), 0u) << message;
        EXPECT_NE(message.find(problem), std::string::npos) << message;
    }
}

TEST(FinalizeScene, RejectsBadScenes) {
    Scene nan = sceneWithEmitters({1.0f}, {{1, 1, 1}}, {false});
    nan.vertices[4].position.y = std::numeric_limits<float>::infinity();
    expectFinalizeError(nan, "non-finite");

    expectFinalizeError(sceneWithEmitters({1.0f}, {{0, 0, 0}}, {false}), "no emitters");

    Scene empty;
    empty.path = "emitters.gltf";
    expectFinalizeError(empty, "no triangles");

    Scene flat = sceneWithEmitters({0.0f}, {{1, 1, 1}}, {false});
    flat.triangles.erase(flat.triangles.begin());
    expectFinalizeError(flat, "degenerate");

    Scene dangling = sceneWithEmitters({1.0f}, {{1, 1, 1}}, {false});
    dangling.triangles[1].i2 = 99;
    expectFinalizeError(dangling, "out of range");

    // Issue 42: an emitter whose power (area * L * pi) overflows 32-bit floats is named, and the
    // total of finite ones may not overflow either; a scene lit by a black environment alone has
    // no light.
    expectFinalizeError(sceneWithEmitters({10.0f}, {glm::vec3(3e37f)}, {false}),
                        "material 1: the power of its triangle 1 overflows 32-bit floats");
    expectFinalizeError(sceneWithEmitters({10.0f, 10.0f}, {glm::vec3(1.5e36f), glm::vec3(1.5e36f)},
                                          {false, false}),  // 2.4e38 each
                        "the emitters' total power overflows");
    Scene blackSky = sceneWithEmitters({1.0f}, {{0, 0, 0}}, {false});
    blackSky.environment.kind = gpu::ENV_CONSTANT;
    expectFinalizeError(blackSky, "no light");
}

}  // namespace
}  // namespace pmcr
