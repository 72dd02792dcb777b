// shaders/methods/pmc_hi/pmc_hi.glsl: deterministic mixture sampling against a C++ reference
// (counts sum to N, their mean is N alpha), the cone density integrating to 1, and the mixture
// density K (eq. 7) equal to the density of what drawing a component by alpha and then a direction
// from it produces (chi-square over the sphere at a fixed shading point lit by two lights, with one
// component per light and with one shared, and under an environment image as one more component).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "distribution_test.h"
#include "gpu_test.h"
#include "render/gpu_scene.h"
#include "scene/scene.h"
#include "scene_builder.h"

namespace pmcr::test {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr uint32_t kSlots = gpu::PMC_HI_MAX_COMPONENTS;

struct PmcHiPush {
    uint32_t mode;
    uint32_t count;
    uint32_t seed;
};

// C++ reference of pmcHiAllocate, in the same float arithmetic.
std::vector<uint32_t> allocateReference(const float* alpha, uint32_t m, uint32_t N, float u) {
    std::vector<uint32_t> counts(kSlots, 0);
    std::vector<float> residual(kSlots, 0.0f);
    uint32_t assigned = 0, lastResidual = 0;
    float residualSum = 0.0f;
    for (uint32_t k = 0; k < m; ++k) {
        const float target = float(N) * std::max(alpha[k], 0.0f);
        const float whole = std::min(std::floor(target), float(N - assigned));
        counts[k] = uint32_t(whole);
        residual[k] = std::max(target - whole, 0.0f);
        assigned += counts[k];
        residualSum += residual[k];
        if (residual[k] > 0.0f) lastResidual = k;
    }
    const uint32_t R = N - assigned;
    if (R == 0) return counts;
    const float scale = residualSum > 0.0f ? float(R) / residualSum : 0.0f;
    float cumulative = 0.0f;
    uint32_t given = 0;
    for (uint32_t k = 0; k < m; ++k) {
        cumulative += residual[k] * scale;
        uint32_t upTo = k >= lastResidual ? R
                                          : uint32_t(std::clamp(std::ceil(cumulative - u), 0.0f, float(R)));
        upTo = std::max(upTo, given);
        counts[k] += upTo - given;
        given = upTo;
    }
    return counts;
}

// A random 16 x 8 environment image with a bright pixel, rotated: its alias table is far from
// uniform, so the environment component's density is put to the test.
Environment testSky() {
    Environment env = randomSkyImage(5, 0.2f, glm::vec3(1.0f));
    env.image.set(3, 2, glm::vec3(20.0f));
    env.rotation = 0.7f;
    return env;
}

// A glossy floor (Lambertian under a GGX coat) in z = 0 with the shading point at the origin,
// and two lights facing down: a quad of two triangles and a single triangle; `env` beside them.
Scene twoLightScene(Environment env = {}) {
    Scene s;
    s.path = "pmc-hi-test.gltf";
    s.materials = {testMaterial(glm::vec3(0.0f), false, 0.5f), testMaterial(glm::vec3(1.0f), false, 1.0f),
                   testMaterial(glm::vec3(3.0f, 2.0f, 1.0f), false, 1.0f)};
    addTriangle(s, {-20, -20, 0}, {20, -20, 0}, {0, 20, 0}, 0);
    addTriangle(s, {-2, -0.5f, 2}, {-2, 0.5f, 2}, {-1, 0.5f, 2}, 1);
    addTriangle(s, {-2, -0.5f, 2}, {-1, 0.5f, 2}, {-1, -0.5f, 2}, 1);
    addTriangle(s, {0.8f, -0.3f, 1.5f}, {0.8f, 0.3f, 1.5f}, {1.4f, 0.0f, 1.5f}, 2);
    Camera camera;
    camera.position = glm::vec3(0, -5, 3);
    s.cameras.push_back(camera);
    s.environment = std::move(env);
    finalizeScene(s);
    return s;
}

gpu::PmcHiTestSetup mixture(bool shared) {
    gpu::PmcHiTestSetup setup{};
    setup.params.populationPerComponent = 2;
    setup.params.iterations = 2;
    setup.params.flags = gpu::PMC_HI_FLAG_RAO_BLACKWELL;
    setup.params.sharedLight = shared ? 1u : 0u;
    setup.params.lightComponents = shared ? 1u : 2u;
    if (shared) {
        setup.alpha[gpu::PMC_HI_BSDF] = 0.4f;
        setup.alpha[gpu::PMC_HI_CONE] = 0.3f;
        setup.alpha[gpu::PMC_HI_LIGHT] = 0.3f;
        setup.coneAxis = glm::normalize(glm::vec3(0.6f, 0.0f, 0.8f));
        setup.coneOneMinusCos = float(1.0 - std::cos(0.25));
    } else {
        setup.alpha[gpu::PMC_HI_BSDF] = 0.3f;
        setup.alpha[gpu::PMC_HI_CONE] = 0.2f;
        setup.alpha[gpu::PMC_HI_LIGHT] = 0.3f;
        setup.alpha[gpu::PMC_HI_LIGHT + 1] = 0.2f;
        setup.coneAxis = glm::normalize(glm::vec3(-0.5f, 0.2f, 1.0f));
        setup.coneOneMinusCos = float(1.0 - std::cos(0.4));
    }
    setup.wo = glm::normalize(glm::vec3(0.5f, 0.2f, 0.8f));
    setup.triangle = 0;
    // The origin: barycentrics of (0, 0, 0) in the floor triangle.
    setup.barycentrics = glm::vec2(0.25f, 0.5f);
    return setup;
}

// One component per light and the environment's after them (slot PMC_HI_LIGHT + 2).
gpu::PmcHiTestSetup mixtureWithEnvironment() {
    gpu::PmcHiTestSetup setup = mixture(false);
    setup.params.flags |= gpu::PMC_HI_FLAG_ENVIRONMENT;
    setup.alpha[gpu::PMC_HI_BSDF] = 0.25f;
    setup.alpha[gpu::PMC_HI_CONE] = 0.15f;
    setup.alpha[gpu::PMC_HI_LIGHT] = 0.2f;
    setup.alpha[gpu::PMC_HI_LIGHT + 1] = 0.15f;
    setup.alpha[gpu::PMC_HI_LIGHT + 2] = 0.25f;
    return setup;
}

// Integral of a density over each cell of `grid` by the midpoint rule on sub x sub points per
// cell. The mixture's densities are discontinuous (the edges of lights and of the cone), where
// the adaptive quadrature's level-to-level error estimate can stop early; a fixed fine rule
// converges there like the cells' boundary length over sub.
std::vector<double> midpointCells(const SphereGrid& grid, const DensityBatch& density, int sub) {
    std::vector<glm::vec3> points;
    std::vector<double> weights;
    for (int c = 0; c < grid.cellCount(); ++c) {
        double z0, z1, p0, p1;
        grid.bounds(c, z0, z1, p0, p1);
        for (int i = 0; i < sub; ++i)
            for (int j = 0; j < sub; ++j)
                points.push_back(glm::vec3(
                    directionFromZPhi(z0 + (i + 0.5) * (z1 - z0) / sub, p0 + (j + 0.5) * (p1 - p0) / sub)));
        weights.push_back((z1 - z0) * (p1 - p0) / (double(sub) * sub));
    }
    const std::vector<double> values = density(points);
    std::vector<double> cells(size_t(grid.cellCount()), 0.0);
    for (size_t k = 0; k < values.size(); ++k)
        cells[k / size_t(sub * sub)] += values[k] * weights[k / size_t(sub * sub)];
    return cells;
}

class PmcHiTest : public GpuTest {
protected:
    std::vector<glm::vec4> call(const GpuScene& scene, const gpu::PmcHiTestSetup& setup,
                                uint32_t mode, uint32_t n, uint32_t values, uint32_t seed,
                                const std::vector<glm::vec4>& directions = {}) {
        auto out = zeros(size_t(n) * values * 16, "pmc-hi results");
        auto in = storage(std::vector<gpu::PmcHiTestSetup>{setup}, "pmc-hi setup");
        auto dirs = storage(directions.empty() ? std::vector<glm::vec4>(1) : directions, "directions");
        run("tests/pmc_hi_test", PmcHiPush{mode, n, seed}, n, {&out, &in, &dirs}, &scene.descriptorSet());
        return out.download<glm::vec4>(size_t(n) * values);
    }

    // The density (component `which` of mode 2's result) at a batch of directions; `which` = -1:
    // the density of what the mixture draws (K, plus the environment's draws that hit a surface
    // and score 0).
    DensityBatch density(const GpuScene& scene, const gpu::PmcHiTestSetup& setup, int which) {
        return [this, &scene, setup, which](const std::vector<glm::vec3>& ws) {
            std::vector<glm::vec4> dirs(ws.size());
            for (size_t i = 0; i < ws.size(); ++i)
                dirs[i] = glm::vec4(ws[i], 0.0f);
            const auto r = call(scene, setup, 2, uint32_t(ws.size()), 1, 0, dirs);
            std::vector<double> v(ws.size());
            for (size_t i = 0; i < ws.size(); ++i)
                v[i] = which < 0 ? double(r[i][0]) + double(r[i][2]) : double(r[i][which]);
            return v;
        };
    }

    // Chi-square of n draws of `setup`'s mixture against the density of what it draws, and that
    // density's integral against the share of draws that produced a direction.
    void expectDrawsMatchDensity(const GpuScene& scene, const gpu::PmcHiTestSetup& setup, uint32_t seed,
                                 const std::string& what) {
        const uint32_t n = 1 << 20;
        const auto r = call(scene, setup, 1, n, 1, seed);
        std::vector<glm::dvec3> directions;
        for (const glm::vec4& v : r) {
            ASSERT_NE(v.w, 2.0f) << "no delta lobe in this material";
            if (v.w == 1.0f) directions.push_back(glm::normalize(glm::dvec3(v)));
        }
        const SphereGrid grid(uniformBreaks(-1, 1, 32), uniformBreaks(0, 2 * kPi, 64));
        const std::vector<double> integrals = midpointCells(grid, density(scene, setup, -1), 32);
        double total = 0.0;
        std::vector<double> expected(integrals.size());
        for (size_t c = 0; c < integrals.size(); ++c) {
            expected[c] = n * integrals[c];
            total += integrals[c];
        }
        EXPECT_TRUE(chi2Passes(grid.histogram(directions), expected, what));
        // K integrates to the share of draws that produced a direction (rough reflections
        // below the surface fail and bsdfPdf leaves them out).
        EXPECT_NEAR(total, double(directions.size()) / n, 4 * std::sqrt(double(directions.size())) / n + 1e-3)
            << what;
    }
};

TEST_F(PmcHiTest, DeterministicMixtureCountsSumToNWithMeanNAlpha) {
    const Scene scene = twoLightScene();
    const GpuScene gpuScene(context(), layout(), scene, 0, 8, 8);
    struct Case {
        std::vector<float> alpha;
        uint32_t perComponent;
    };
    const std::vector<Case> cases = {
        {{0.37f, 0.11f, 0.29f, 0.23f}, 2},
        {{1.0f / 3, 0.0f, 1.0f / 3, 1.0f / 3}, 2},
        {{0.5f, 0.2f, 0.3f}, 2},
        {{0.05f, 0.0f, 0.9f, 0.05f, 0.0f}, 1},
        {{0.02f, 0.13f, 0.1f, 0.1f, 0.05f, 0.2f, 0.1f, 0.1f, 0.1f, 0.1f}, 3},
    };
    const uint32_t n = 4096;
    uint32_t seed = 11;
    for (const Case& c : cases) {
        gpu::PmcHiTestSetup setup{};
        const uint32_t m = uint32_t(c.alpha.size());
        for (uint32_t k = 0; k < m; ++k)
            setup.alpha[k] = c.alpha[k];
        setup.m = m;
        setup.N = c.perComponent * m;
        const auto r = call(gpuScene, setup, 0, n, 3, ++seed);
        std::vector<double> mean(kSlots, 0.0);
        int mismatches = 0;
        for (uint32_t i = 0; i < n; ++i) {
            uint32_t sum = 0;
            std::vector<uint32_t> counts(kSlots);
            for (uint32_t k = 0; k < kSlots; ++k) {
                counts[k] = uint32_t(r[3 * i + k / 4][int(k % 4)]);
                sum += counts[k];
                mean[k] += counts[k];
                const double target = double(setup.N) * (k < m ? c.alpha[k] : 0.0);
                ASSERT_GE(counts[k] + 1e-4, std::floor(target - 1e-4)) << "slot " << k;
                ASSERT_LE(counts[k], std::floor(target + 1e-4) + 1) << "slot " << k;
            }
            ASSERT_EQ(sum, setup.N) << "DMS counts must sum to N";
            // The C++ reference at the same u, in the same float arithmetic.
            const auto ref = allocateReference(c.alpha.data(), m, setup.N, (float(i) + 0.5f) / float(n));
            mismatches += ref != counts;
        }
        EXPECT_LE(mismatches, int(n / 1000)) << "GLSL and C++ allocations differ";
        // u stratified over [0, 1): the mean count is N alpha_k up to the stratification.
        for (uint32_t k = 0; k < m; ++k)
            EXPECT_NEAR(mean[k] / n, setup.N * c.alpha[k], 2.0 / n + 1e-5) << "slot " << k;
    }
}

TEST_F(PmcHiTest, ConePdfIntegratesToOne) {
    const Scene scene = twoLightScene();
    const GpuScene gpuScene(context(), layout(), scene, 0, 8, 8);
    for (bool shared : {false, true}) {
        const gpu::PmcHiTestSetup setup = mixture(shared);
        const SphereGrid grid(uniformBreaks(-1, 1, 64), uniformBreaks(0, 2 * kPi, 128));
        double total = 0.0;
        for (double v : midpointCells(grid, density(gpuScene, setup, 1), 16))
            total += v;
        EXPECT_NEAR(total, 1.0, 2e-3) << (shared ? "shared" : "per light");
    }
}

TEST_F(PmcHiTest, MixtureDensityIsWhatTheMixtureDraws) {
    const Scene scene = twoLightScene();
    const GpuScene gpuScene(context(), layout(), scene, 0, 8, 8);
    ASSERT_EQ(gpuScene.lightGroups().lights.size(), 2u);
    uint32_t seed = 70;
    for (bool shared : {false, true})
        expectDrawsMatchDensity(gpuScene, mixture(shared), ++seed,
                                shared ? "PMC-HI mixture, shared light" : "PMC-HI mixture, two lights");
}

// The environment component: its draws (envSample) against envPdf where the ray escapes, and
// where it hits a light or the floor's far side, against a_env envPdf outside K (those draws
// score 0, and K holds the density of what scores).
TEST_F(PmcHiTest, MixtureDensityWithTheEnvironmentIsWhatTheMixtureDraws) {
    const Scene scene = twoLightScene(testSky());
    const GpuScene gpuScene(context(), layout(), scene, 0, 8, 8);
    ASSERT_EQ(gpuScene.info().envKind, gpu::ENV_IMAGE);
    expectDrawsMatchDensity(gpuScene, mixtureWithEnvironment(), 90, "PMC-HI mixture, two lights and sky");
    // The environment component alone: its density integrates to 1 over the sphere.
    gpu::PmcHiTestSetup envOnly = mixtureWithEnvironment();
    for (uint32_t k = 0; k < kSlots; ++k) envOnly.alpha[k] = 0.0f;
    envOnly.alpha[gpu::PMC_HI_LIGHT + 2] = 1.0f;
    const SphereGrid grid(uniformBreaks(-1, 1, 64), uniformBreaks(0, 2 * kPi, 128));
    double total = 0.0;
    for (double v : midpointCells(grid, density(gpuScene, envOnly, -1), 8)) total += v;
    EXPECT_NEAR(total, 1.0, 2e-3);
}

}  // namespace
}  // namespace pmcr::test
