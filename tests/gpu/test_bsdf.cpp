// shaders/common/bsdf.glsl over a grid of materials and outgoing directions (pbrt-v4
// `bsdfs_test.cpp` habits):
//   - directions bsdfSample draws through non-delta lobes follow bsdfPdf (chi-square over graded
//     cells of the sphere), delta samples come with the frequency of their discrete probability;
//   - bsdfPdf integrates to 1 minus the delta probability minus the share of failed samples;
//   - a non-delta sample carries bsdfEval and bsdfPdf of its direction (its f and pdf come from
//     bsdfEvalPdf, the kernels' one-pass form, so this checks that against the lobe-by-lobe sums);
//   - the directional albedo (energy, transmission scaled back by eta^2) is at most 1, exactly 1
//     for white smooth glass and the base colour for the Lambertian;
//   - f is reciprocal for reflection and obeys f(wo, wi) / eta_o^2 = f(wi, wo) / eta_i^2 for
//     transmission (radiance convention; eta 1 through a thin sheet);
//   - the thin sheet (thin-walled transmission) reflects R' = 2R / (1 + R) and transmits
//     (1 - R) / (1 + R) of the light at every angle (the closed form of pbrt-v4's sum
//     R + T^2 R / (1 - R^2) without absorption), and its rough form tends to it as alpha -> 0;
//   - a BLEND material passes a share 1 - coverage straight through (a delta of eta 1) and
//     scales its own lobes by the coverage.
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "distribution_test.h"
#include "gpu_test.h"

namespace pmcr::test {
namespace {

constexpr double kPi = std::numbers::pi;

struct BsdfPush {
    uint32_t mode;
    uint32_t count;
    uint32_t seed;
    uint32_t frontSide;
    glm::vec3 baseColor;
    float metallic;
    float roughness;
    float transmission;
    float ior;
    glm::vec3 wo;
    uint32_t thin;
    float coverage;
    float specularWeight;
    glm::vec3 specularColor;
    float clearcoat;
    float clearcoatRoughness;
    glm::vec3 sheenColor;
    float sheenRoughness;
    glm::vec3 clearcoatNormal;
    uint32_t adjoint;
};

enum BsdfMode : uint32_t { Sample = 0, Eval, Info };

// bsdf.glsl lobe ids (LOBE_*).
enum Lobe : uint32_t { LobeDiffuse = 1, LobeCoat, LobeConductor, LobeDielectric, LobePass, LobeClearcoat, LobeSheen };

struct MaterialCase {
    std::string name;
    glm::vec3 baseColor;
    float metallic;
    float roughness;
    float transmission;
    float ior;
    bool frontSide;
    bool thin = false;      // thin-walled transmission
    float coverage = 1.0f;  // alphaMode BLEND
    float specular = -1.0f;  // KHR_materials_specular's weight (negative: no extension)
    glm::vec3 specularColor = glm::vec3(1.0f);
    float clearcoat = 0.0f;  // KHR_materials_clearcoat
    float clearcoatRoughness = 0.0f;
    glm::vec3 sheenColor = glm::vec3(0.0f);  // KHR_materials_sheen
    float sheenRoughness = 0.0f;
    // The clear coat's own normal in the local frame (bsdf.glsl clearcoatNormal); zero: the
    // shading normal's.
    glm::vec3 clearcoatNormal = glm::vec3(0.0f);
    bool adjoint = false;  // the coat's adjoint term, as light-side walks evaluate it
    bool tilted() const { return clearcoat > 0.0f && clearcoatNormal != glm::vec3(0.0f); }
};

// The material `m` under a clear coat whose normal is `n` (normalized here).
MaterialCase withCoatNormal(MaterialCase m, const char* name, glm::vec3 n) {
    m.name = name;
    m.clearcoatNormal = glm::normalize(n);
    return m;
}

// A material with a sheen of `colour` and `roughness` over the given one.
MaterialCase withSheen(MaterialCase m, const char* name, glm::vec3 colour, float roughness) {
    m.name = name;
    m.sheenColor = colour;
    m.sheenRoughness = roughness;
    return m;
}

const glm::vec3 kColour(0.8f, 0.5f, 0.3f);
const glm::vec3 kWhite(1.0f);

const std::vector<MaterialCase>& materials() {
    static const std::vector<MaterialCase> cases = {
        {"diffuse", kColour, 0, 1, 0, 1.5f, true},
        {"coat smooth", kColour, 0, 0, 0, 1.5f, true},
        {"coat 0.05", kColour, 0, 0.05f, 0, 1.5f, true},
        {"coat 0.3", kColour, 0, 0.3f, 0, 1.5f, true},
        {"coat 0.7", kColour, 0, 0.7f, 0, 1.5f, true},
        {"conductor smooth", glm::vec3(0.9f, 0.6f, 0.3f), 1, 0, 0, 1.5f, true},
        {"conductor 0.1", glm::vec3(0.9f, 0.6f, 0.3f), 1, 0.1f, 0, 1.5f, true},
        {"conductor 0.5", glm::vec3(0.9f, 0.6f, 0.3f), 1, 0.5f, 0, 1.5f, true},
        {"glass smooth entering", kWhite, 0, 0, 1, 1.5f, true},
        {"glass smooth exiting", kWhite, 0, 0, 1, 1.5f, false},
        {"glass 0.1 entering", kWhite, 0, 0.1f, 1, 1.5f, true},
        {"glass 0.1 exiting", kWhite, 0, 0.1f, 1, 1.5f, false},
        {"glass 0.4 entering", kWhite, 0, 0.4f, 1, 1.5f, true},
        {"glass 0.4 exiting", kWhite, 0, 0.4f, 1, 1.5f, false},
        {"metallic 0.5", kColour, 0.5f, 0.3f, 0, 1.5f, true},
        {"transmission 0.5", glm::vec3(0.9f, 0.8f, 0.7f), 0, 0.3f, 0.5f, 1.5f, true},
        {"transmission 0.5 smooth", glm::vec3(0.9f, 0.8f, 0.7f), 0, 0, 0.5f, 1.5f, true},
        {"thin smooth front", kWhite, 0, 0, 1, 1.5f, true, true},
        {"thin smooth back", kWhite, 0, 0, 1, 1.5f, false, true},
        {"thin smooth tinted half", glm::vec3(0.9f, 0.8f, 0.7f), 0, 0, 0.5f, 1.33f, true, true},
        {"thin 0.1", kWhite, 0, 0.1f, 1, 1.5f, true, true},
        {"thin 0.4 back", kWhite, 0, 0.4f, 1, 1.5f, false, true},
        {"thin 0.3 tinted", glm::vec3(0.9f, 0.8f, 0.7f), 0.2f, 0.3f, 0.7f, 1.5f, true, true},
        {"blend diffuse", kColour, 0, 1, 0, 1.5f, true, false, 0.3f},
        {"blend coat 0.3", kColour, 0, 0.3f, 0, 1.5f, true, false, 0.6f},
        {"blend glass smooth", kWhite, 0, 0, 1, 1.5f, true, false, 0.3f},
        {"blend glass 0.2 exiting", kWhite, 0, 0.2f, 1, 1.5f, false, false, 0.5f},
        {"blend thin 0.3", kWhite, 0, 0.3f, 1, 1.5f, true, true, 0.4f},
        {"blend transparent", kColour, 0, 0.5f, 0, 1.5f, true, false, 0.0f},
        {"specular smooth", kColour, 0, 0, 0, 1.5f, true, false, 1, 0.7f, glm::vec3(1.0f, 0.5f, 0.2f)},
        {"specular 0.3", kColour, 0, 0.3f, 0, 1.5f, true, false, 1, 0.7f, glm::vec3(1.0f, 0.5f, 0.2f)},
        {"specular bright 0.2", kWhite, 0, 0.2f, 0, 1.5f, true, false, 1, 1.0f, glm::vec3(8.0f, 1.0f, 0.0f)},
        {"specular off 0.5", kColour, 0.3f, 0.5f, 0.2f, 1.5f, true, false, 1, 0.0f, glm::vec3(1.0f)},
        {"clearcoat smooth diffuse", kColour, 0, 1, 0, 1.5f, true, false, 1, -1, kWhite, 1.0f, 0.0f},
        {"clearcoat 0.1 coat 0.5", kColour, 0, 0.5f, 0, 1.5f, true, false, 1, -1, kWhite, 0.8f, 0.1f},
        {"clearcoat 0.3 conductor smooth", glm::vec3(0.9f, 0.6f, 0.3f), 1, 0, 0, 1.5f, true, false, 1, -1, kWhite, 1.0f, 0.3f},
        {"clearcoat smooth glass 0.2", kWhite, 0, 0.2f, 1, 1.5f, true, false, 1, -1, kWhite, 1.0f, 0.0f},
        {"clearcoat 0.2 glass back", kWhite, 0, 0, 1, 1.5f, false, false, 1, -1, kWhite, 1.0f, 0.2f},
        {"clearcoat 0.2 blend", kColour, 0, 0.4f, 0, 1.5f, true, false, 0.5f, -1, kWhite, 1.0f, 0.2f},
        withSheen({"", kWhite, 0, 1, 0, 1.5f, true}, "sheen white over white", kWhite, 0.5f),
        withSheen({"", glm::vec3(0.1f, 0.1f, 0.4f), 0, 1, 0, 1.5f, true}, "sheen cloth 0.3",
                  glm::vec3(0.8f, 0.8f, 1.0f), 0.3f),
        withSheen({"", kColour, 0, 0.4f, 0, 1.5f, true}, "sheen 0.8 over coat", glm::vec3(1.0f, 0.5f, 0.5f), 0.8f),
        withSheen({"", kWhite, 0, 0.2f, 1, 1.5f, true, false, 0.7f, -1, kWhite, 1.0f, 0.1f},
                  "sheen glass clearcoat blend", glm::vec3(0.5f), 0.4f),
        withSheen({"", kWhite, 0, 0, 1, 1.5f, false}, "sheen smooth glass back", kWhite, 0.6f),
        // A coat normal of its own, tilted 30 to 37 degrees: towards wo (whose mirror about it
        // then leaves below the surface at some angles), away from it and out of its plane.
        // (Not by exactly 36.87 degrees away: at cos(theta_o) 0.6 wo would graze the coat, whose
        // F = 1 there leaves nothing to the lobes below, so every sample fails on f = 0 where
        // bsdfPdf is not 0, which (b) below does not allow for.)
        withCoatNormal({"", kColour, 0, 1, 0, 1.5f, true, false, 1, -1, kWhite, 1.0f, 0.0f},
                       "clearcoat tilted smooth diffuse", glm::vec3(-0.5f, 0.0f, 0.866f)),
        withCoatNormal({"", kColour, 0, 0.4f, 0, 1.5f, true, false, 1, -1, kWhite, 0.9f, 0.2f},
                       "clearcoat tilted 0.2 coat 0.4", glm::vec3(0.3f, 0.4f, 0.866f)),
        withCoatNormal({"", kColour, 0, 1, 0, 1.5f, true, false, 1, -1, kWhite, 1.0f, 0.05f},
                       "clearcoat tilted 0.05 diffuse", glm::vec3(-0.55f, 0.0f, 0.835f)),
    };
    return cases;
}

// cos(theta_o) of the outgoing directions: near normal to grazing (about 88 degrees).
constexpr double kCosThetaO[] = {0.95, 0.6, 0.25, 0.04};

glm::vec3 woAt(double cosTheta) {
    return glm::vec3(float(std::sqrt(1.0 - cosTheta * cosTheta)), 0.0f, float(cosTheta));
}

struct BsdfSampleResult {
    glm::vec3 wi;
    float pdf;
    glm::vec3 f;
    float flags;  // ok + 2 delta + 4 lobe
    bool ok() const { return (uint32_t(flags) & 1u) != 0; }
    bool delta() const { return (uint32_t(flags) & 2u) != 0; }
    uint32_t lobe() const { return uint32_t(flags) >> 2; }
};
static_assert(sizeof(BsdfSampleResult) == 32);

class BsdfTest : public GpuTest {
protected:
    BsdfPush push(const MaterialCase& m, BsdfMode mode, uint32_t count, glm::vec3 wo,
                  uint32_t seed = 0, bool frontSide = true) {
        BsdfPush p{};
        p.mode = mode;
        p.count = count;
        p.seed = seed;
        p.frontSide = frontSide ? 1u : 0u;
        p.baseColor = m.baseColor;
        p.metallic = m.metallic;
        p.roughness = m.roughness;
        p.transmission = m.transmission;
        p.ior = m.ior;
        p.wo = wo;
        p.thin = m.thin ? 1u : 0u;
        p.coverage = m.coverage;
        p.specularWeight = m.specular;
        p.specularColor = m.specularColor;
        p.clearcoat = m.clearcoat;
        p.clearcoatRoughness = m.clearcoatRoughness;
        p.sheenColor = m.sheenColor;
        p.sheenRoughness = m.sheenRoughness;
        p.clearcoatNormal = m.clearcoatNormal;
        p.adjoint = m.adjoint ? 1u : 0u;
        return p;
    }
    std::vector<BsdfSampleResult> sample(const MaterialCase& m, glm::vec3 wo, uint32_t n,
                                         uint32_t seed) {
        auto unused = zeros(16);
        auto out = zeros(size_t(n) * sizeof(BsdfSampleResult), "bsdf samples");
        run("tests/bsdf_test", push(m, Sample, n, wo, seed, m.frontSide), n, {&unused, &out});
        return out.download<BsdfSampleResult>(n);
    }
    // (bsdfEval, bsdfPdf) for each (wo, wi) pair.
    std::vector<glm::vec4> eval(const MaterialCase& m, const std::vector<glm::vec3>& wos,
                                const std::vector<glm::vec3>& wis, bool frontSide) {
        std::vector<glm::vec4> in;
        in.reserve(2 * wis.size());
        for (size_t i = 0; i < wis.size(); ++i) {
            in.push_back(glm::vec4(wos[i], 0.0f));
            in.push_back(glm::vec4(wis[i], 0.0f));
        }
        const uint32_t n = uint32_t(wis.size());
        auto inBuf = storage(in, "bsdf queries");
        auto out = zeros(size_t(n) * 16, "bsdf values");
        run("tests/bsdf_test", push(m, Eval, n, glm::vec3(0, 0, 1), 0, frontSide), n,
            {&inBuf, &out});
        return out.download<glm::vec4>(n);
    }
    DensityBatch pdfAt(const MaterialCase& m, glm::vec3 wo) {
        return [=, this](const std::vector<glm::vec3>& wis) {
            const auto r = eval(m, std::vector<glm::vec3>(wis.size(), wo), wis, m.frontSide);
            std::vector<double> v(r.size());
            for (size_t i = 0; i < r.size(); ++i)
                v[i] = r[i].w;
            return v;
        };
    }
    // lobeSelectProbabilities(wo) and (dielectricReflectance(wo.z), eta, bsdfHasNonDelta, wPass).
    std::pair<glm::vec4, glm::vec4> info(const MaterialCase& m, glm::vec3 wo) {
        const auto r = infoAll(m, wo);
        return {r[0], r[1]};
    }
    // ... and (clearcoatLobeProbability, clearcoatAttenuation(wo), 0, 0).
    std::vector<glm::vec4> infoAll(const MaterialCase& m, glm::vec3 wo) {
        auto unused = zeros(16);
        auto out = zeros(48, "bsdf info");
        run("tests/bsdf_test", push(m, Info, 1, wo, 0, m.frontSide), 1, {&unused, &out});
        return out.download<glm::vec4>(3);
    }
    void checkSampling(const MaterialCase& m, double cosO, uint32_t seed);
};

// Cells graded towards the mirror direction above the surface and the refracted one below, and
// towards phi = pi (both lie opposite wo, which is at phi = 0), by the lobe width ~ alpha.
SphereGrid lobeGrid(const MaterialCase& m, glm::vec3 wo, float eta) {
    const double alpha = std::max(double(m.roughness) * m.roughness, 1e-3);
    const double zr = wo.z, sinR = std::sqrt(1 - zr * zr);
    const double sinT = sinR / eta;
    const double zt = sinT < 1.0 ? -std::sqrt(1 - sinT * sinT) : -zr;
    const double zFirst = std::max({0.25 * alpha * sinR, 0.25 * alpha * alpha, 1e-5});
    std::vector<double> z = gradedBreaks(-1.0, zt, 0.0, 16, zFirst);
    z.pop_back();
    for (double b : gradedBreaks(0.0, zr, 1.0, 16, zFirst))
        z.push_back(b);
    const double phiFirst = 0.25 * alpha / std::max(sinR, alpha);
    return SphereGrid(z, gradedBreaks(0.0, kPi, 2 * kPi, 32, phiFirst));
}

std::string describe(const MaterialCase& m, double cosO) {
    return m.name + ", cos(theta_o) " + std::to_string(cosO);
}

// Sampling against the stated densities, normalisation, sample consistency and energy for one
// material and outgoing direction.
void BsdfTest::checkSampling(const MaterialCase& m, double cosO, uint32_t seed) {
    const uint32_t n = 1 << 17;
    const glm::vec3 wo = woAt(cosO);
    const auto all = infoAll(m, wo);
    const glm::vec4 p = all[0], extra = all[1];
    const float pClearcoat = all[2].x, pSheen = all[2].w;
    const float fresnel = extra.x, eta = extra.y;
    const bool smooth = m.roughness * m.roughness < 1e-3f;  // bsdfSmooth: alpha < SMOOTH_ALPHA
    const bool clearcoatSmooth = m.clearcoatRoughness * m.clearcoatRoughness < 1e-3f;
    EXPECT_NEAR(extra.w, 1.0 - m.coverage, 1e-6) << "wPass";
    EXPECT_NEAR(p.x + p.y + p.z + p.w + extra.w + pClearcoat + pSheen, 1.0, 1e-5) << "lobe probabilities";
    // (A tilted coat reflects nothing where wo, or its smooth mirror, is below a horizon.)
    if (!m.tilted())
        EXPECT_EQ(pClearcoat > 0.0f, m.clearcoat > 0.0f && m.frontSide) << "clear coat on the front only";

    // Discrete probabilities of the delta outcomes, from the lobe selection probabilities.
    // Categories: coat mirror, conductor mirror, glass reflection, glass transmission, pass,
    // clear coat mirror.
    constexpr int kCategories = 6;
    double deltaExpected[kCategories] = {0, 0, 0, 0, extra.w, clearcoatSmooth ? pClearcoat : 0.0};
    if (smooth) {
        deltaExpected[0] = p.y;
        deltaExpected[1] = p.z;
        deltaExpected[2] = p.w * fresnel;
        deltaExpected[3] = p.w * (1 - fresnel);
    }
    double deltaTotal = 0.0;
    for (double d : deltaExpected)
        deltaTotal += d;

    const auto samples = sample(m, wo, n, seed);
    double deltaObserved[kCategories] = {0, 0, 0, 0, 0, 0};
    double failed = 0.0;
    glm::dvec3 energy(0.0), energySq(0.0);
    std::vector<glm::dvec3> directions;
    std::vector<size_t> nonDelta;
    for (size_t i = 0; i < samples.size(); ++i) {
        const BsdfSampleResult& s = samples[i];
        if (!s.ok()) {
            failed += 1.0;
            continue;
        }
        ASSERT_NEAR(glm::length(s.wi), 1.0f, 1e-4f) << i;
        ASSERT_GT(s.pdf, 0.0f) << i;
        ASSERT_TRUE(std::isfinite(s.pdf) && std::isfinite(s.f.x) && std::isfinite(s.f.y) &&
                    std::isfinite(s.f.z))
            << i;
        ASSERT_GE(std::min({s.f.x, s.f.y, s.f.z}), 0.0f) << i;
        // Energy weight: f |cos| / pdf, refraction scaled back by eta^2 (radiance mode
        // divides it by eta^2; a pass crosses no interface).
        glm::dvec3 w = glm::dvec3(s.f) * std::abs(double(s.wi.z)) / double(s.pdf);
        if (s.wi.z < 0.0f && s.lobe() == LobeDielectric)
            w *= double(eta) * eta;
        energy += w;
        energySq += w * w;
        if (s.delta()) {
            ASSERT_TRUE(smooth || s.lobe() == LobePass || (s.lobe() == LobeClearcoat && clearcoatSmooth))
                << "delta sample from a rough material, lobe " << s.lobe();
            int category = -1;
            if (s.lobe() == LobeCoat)
                category = 0;
            if (s.lobe() == LobeConductor)
                category = 1;
            if (s.lobe() == LobeDielectric)
                category = s.wi.z > 0.0f ? 2 : 3;
            if (s.lobe() == LobePass)
                category = 4;
            if (s.lobe() == LobeClearcoat)
                category = 5;
            ASSERT_GE(category, 0) << "delta sample of lobe " << s.lobe();
            ASSERT_NEAR(s.pdf, deltaExpected[category], 1e-5) << "discrete probability";
            if (category == 4 || (category == 3 && m.thin)) {
                // Straight on: a pass, or through a thin sheet.
                ASSERT_EQ(s.wi, -wo) << "straight through";
            } else if (category == 5 && m.tilted()) {
                // The mirror about the coat's normal.
                const glm::vec3 n = m.clearcoatNormal;
                const glm::vec3 mirror = 2.0f * glm::dot(wo, n) * n - wo;
                ASSERT_LT(glm::length(s.wi - mirror), 1e-5f) << "mirror about the coat normal";
                ASSERT_GT(s.wi.z, 0.0f);
            } else if (s.wi.z > 0.0f) {
                ASSERT_EQ(s.wi, glm::vec3(-wo.x, -wo.y, wo.z)) << "mirror direction";
            } else {
                // Snell's law in the plane of incidence, on the far side of the normal.
                ASSERT_NEAR(-s.wi.x * eta, wo.x, 1e-5f);
                ASSERT_EQ(s.wi.y, 0.0f);
            }
            deltaObserved[category] += 1.0;
        } else {
            directions.push_back(glm::dvec3(s.wi));
            nonDelta.push_back(i);
        }
    }
    const std::string what = describe(m, cosO);

    // (c) A non-delta sample carries bsdfEval and bsdfPdf of its direction.
    {
        const size_t k = std::min<size_t>(nonDelta.size(), 2048);
        std::vector<glm::vec3> wis(k);
        for (size_t j = 0; j < k; ++j)
            wis[j] = samples[nonDelta[j]].wi;
        const auto values = eval(m, std::vector<glm::vec3>(k, wo), wis, m.frontSide);
        for (size_t j = 0; j < k; ++j) {
            const BsdfSampleResult& s = samples[nonDelta[j]];
            ASSERT_NEAR(s.pdf, values[j].w, 1e-5f * values[j].w) << what << " sample " << j;
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(s.f[c], values[j][c], 1e-5f * values[j][c]) << what << " sample " << j;
        }
    }

    // (a) Sampled directions against bsdfPdf integrated per cell, delta outcomes against their
    // probabilities, in one Pearson test.
    const SphereGrid grid = lobeGrid(m, wo, eta);
    const CellIntegrals integrals = integrateCells(grid, pdfAt(m, wo), countTolerance(n));
    std::vector<double> observed = grid.histogram(directions);
    std::vector<double> expected = expectedCounts(grid, integrals, n, directions, pdfAt(m, wo));
    int categories = 0;
    for (int c = 0; c < kCategories; ++c) {
        observed.push_back(deltaObserved[c]);
        expected.push_back(n * deltaExpected[c]);
        categories += deltaExpected[c] > 0.0 ? 1 : 0;
    }
    EXPECT_EQ(extra.z != 0.0f, integrals.total() > 0.0) << what << ": bsdfHasNonDelta";
    if (integrals.total() > 0.0 || categories > 1) {
        EXPECT_TRUE(chi2Passes(observed, expected, "bsdfSample " + what));
    } else {
        // One delta outcome only: every sample takes it.
        for (int c = 0; c < kCategories; ++c)
            EXPECT_EQ(deltaObserved[c], n * deltaExpected[c]) << what;
    }

    // (b) bsdfPdf integrates to the share of samples that are neither delta nor failed. (Rough
    // reflection may leave the hemisphere: such samples fail, and pdf excludes them.)
    const double failedShare = failed / n;
    const double nonDeltaShare = 1.0 - deltaTotal - failedShare;
    EXPECT_NEAR(integrals.total(), nonDeltaShare,
                2.0 * integrals.error + 5.0 * std::sqrt(failedShare * (1 - failedShare) / n) + 2e-4)
        << what << ": integral of bsdfPdf (delta " << deltaTotal << ", failed " << failedShare
        << ")";

    // (d) Energy: the directional albedo is at most 1.
    const glm::dvec3 mean = energy / double(n);
    const glm::dvec3 stdError =
        glm::sqrt(glm::max(energySq / double(n) - mean * mean, 0.0) / double(n));
    for (int c = 0; c < 3; ++c)
        EXPECT_LE(mean[c], 1.0 + 5.0 * stdError[c] + 1e-4) << what << " albedo channel " << c;
    // White furnace: smooth white glass, solid or thin, alone or under a BLEND pass, loses
    // nothing.
    if (m.name.rfind("glass smooth", 0) == 0 || m.name.rfind("thin smooth front", 0) == 0 ||
        m.name.rfind("thin smooth back", 0) == 0 || m.name == "blend glass smooth" ||
        m.name == "blend transparent") {
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(mean[c], 1.0, 1e-4) << what << " white glass";
    }
    if (m.name == "diffuse") {
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(mean[c], m.baseColor[c], 1e-4) << what;
    }
    if (m.name == "blend diffuse") {
        // coverage * Lambertian albedo + (1 - coverage) passed on.
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(mean[c], m.coverage * m.baseColor[c] + (1 - m.coverage),
                        5.0 * stdError[c] + 1e-4)
                << what;
    }
}

class BsdfSampling : public BsdfTest, public ::testing::WithParamInterface<size_t> {};

TEST_P(BsdfSampling, MatchesPdfAndConservesEnergy) {
    const MaterialCase& m = materials()[GetParam()];
    uint32_t seed = 1000 + 16 * uint32_t(GetParam());
    for (double cosO : kCosThetaO) {
        SCOPED_TRACE(describe(m, cosO));
        checkSampling(m, cosO, ++seed);
        if (HasFatalFailure())
            return;
    }
}

INSTANTIATE_TEST_SUITE_P(Materials, BsdfSampling, ::testing::Range<size_t>(0, materials().size()),
                         [](const ::testing::TestParamInfo<size_t>& info) {
                             std::string name = materials()[info.param].name;
                             for (char& c : name)
                                 if (!std::isalnum(static_cast<unsigned char>(c)))
                                     c = '_';
                             return name;
                         });

TEST_F(BsdfTest, Reciprocity) {
    std::mt19937 gen(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    auto upper = [&] { return glm::vec3(directionFromZPhi(u(gen), 2 * kPi * u(gen))); };
    const size_t n = 2048;
    std::vector<glm::vec3> a(n), b(n), bLower(n), aFlipped(n), bFlipped(n);
    for (size_t i = 0; i < n; ++i) {
        a[i] = upper();
        b[i] = upper();
        bLower[i] = glm::vec3(b[i].x, b[i].y, -b[i].z);
        // Seen from the other side the local frame flips z (an isotropic BSDF does not mind the
        // reflection of the tangent plane this amounts to).
        aFlipped[i] = glm::vec3(a[i].x, a[i].y, -a[i].z);
        bFlipped[i] = b[i];
    }
    for (const MaterialCase& m : materials()) {
        // (A tilted coat's term is not symmetric: ClearcoatNormalAdjoint checks its adjoint.)
        if (!m.frontSide || m.tilted())
            continue;
        SCOPED_TRACE(m.name);
        // Reflection: f(a, b) = f(b, a).
        const auto ab = eval(m, a, b, true), ba = eval(m, b, a, true);
        for (size_t i = 0; i < n; ++i)
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(ab[i][c], ba[i][c], 2e-4f * std::max(ab[i][c], 1.0f)) << "pair " << i;
        if (m.transmission == 0.0f)
            continue;
        // Transmission from outside (eta 1) to inside (eta = ior) and back:
        // f(wo, wi) / eta_o^2 = f(wi, wo) / eta_i^2. A thin sheet has air on both sides.
        const auto in = eval(m, a, bLower, true), out = eval(m, bFlipped, aFlipped, false);
        const float ior2 = m.thin ? 1.0f : m.ior * m.ior;
        for (size_t i = 0; i < n; ++i)
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(in[i][c], out[i][c] / ior2, 2e-4f * std::max(in[i][c], 1.0f))
                    << "pair " << i;
    }
}

// Unpolarised Fresnel reflectance of a dielectric interface from the side of index 1 (the
// Fresnel equations, Hecht, Optics, 5th ed., sec. 4.6.2), in double precision.
double fresnelReference(double cosI, double eta) {
    const double sin2T = (1.0 - cosI * cosI) / (eta * eta);
    const double cosT = std::sqrt(1.0 - sin2T);
    const double parallel = (eta * cosI - cosT) / (eta * cosI + cosT);
    const double perpendicular = (cosI - eta * cosT) / (cosI + eta * cosT);
    return 0.5 * (parallel * parallel + perpendicular * perpendicular);
}

// KHR_materials_specular on the smooth coat: the mirror's weight f |cos| (of the coat's delta
// sample) is specular * (f0 + (1 - f0) w), f0 = min(F0 * colour, 1), w = (F - F0) / (1 - F0)
// (bsdf.glsl coatFresnel; the extension's fresnel_mix with F's own rise), at angles from normal
// to grazing; weight 1 and colour 1 give F itself, and the Lambertian base keeps
// (1 - max channel)^2 of its light at normal incidence (the extension's max_value(fr)).
TEST_F(BsdfTest, SpecularExtensionWeightsAndTintsTheCoat) {
    const double ior = 1.5, F0 = 0.04;
    for (const auto& [weight, colour] :
         {std::pair{1.0f, glm::vec3(1.0f)}, std::pair{0.6f, glm::vec3(1.0f, 0.5f, 0.25f)},
          std::pair{1.0f, glm::vec3(30.0f, 1.0f, 0.0f)}}) {
        const MaterialCase m{"specular", kColour, 0, 0, 0, float(ior), true, false, 1, weight, colour};
        for (const double cosO : {1.0, 0.8, 0.5, 0.2, 0.05}) {
            const glm::vec3 wo = woAt(cosO);
            const double F = fresnelReference(wo.z, ior);
            const double w = (F - F0) / (1.0 - F0);
            const auto samples = sample(m, wo, 4096, 5);
            int mirrors = 0;
            for (const BsdfSampleResult& s : samples) {
                if (!s.ok() || !s.delta() || s.lobe() != LobeCoat) continue;
                ++mirrors;
                for (int c = 0; c < 3; ++c) {
                    const double f0 = std::min(F0 * colour[c], 1.0);
                    ASSERT_NEAR(s.f[c] * wo.z, weight * (f0 + (1.0 - f0) * w), 2e-5)
                        << "weight " << weight << ", cos " << cosO << ", channel " << c;
                }
            }
            EXPECT_GT(mirrors, 0) << "cos " << cosO;
        }
        // The base at normal incidence in and out: baseColor / pi (1 - max Fc(1))^2.
        const glm::vec3 n(0, 0, 1);
        const auto v = eval(m, {n}, {n}, true);
        const double fc = weight * std::min(std::max({F0 * colour.x, F0 * colour.y, F0 * colour.z}), 1.0);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(v[0][c], kColour[c] / kPi * (1 - fc) * (1 - fc), 1e-5) << "channel " << c;
    }
}

// KHR_materials_clearcoat over a Lambertian base: the smooth coat's mirror weight is
// c F(1.5, cos) (the extension's coat of F0 0.04, with the exact Fresnel factor) and the base
// below keeps (1 - c F(cos_o)) (1 - c F(cos_i)) of its value; seen from the back (no coat there)
// the glass below is attenuated once, on the front side only.
TEST_F(BsdfTest, ClearcoatReflectsAndAttenuatesAsLayered) {
    for (const float c : {1.0f, 0.4f}) {
        const MaterialCase m{"clearcoat", kColour, 0, 1, 0, 1.5f, true, false, 1, -1, kWhite, c, 0.0f};
        for (const double cosO : {1.0, 0.7, 0.3, 0.05}) {
            const glm::vec3 wo = woAt(cosO);
            const double F = fresnelReference(wo.z, 1.5);
            int mirrors = 0;
            for (const BsdfSampleResult& s : sample(m, wo, 4096, 9)) {
                if (!s.ok() || !s.delta()) continue;
                ASSERT_EQ(s.lobe(), LobeClearcoat);
                ++mirrors;
                for (int k = 0; k < 3; ++k)
                    ASSERT_NEAR(s.f[k] * wo.z, c * F, 2e-6) << "c " << c << ", cos " << cosO;
            }
            EXPECT_GT(mirrors, 0);
            const glm::vec3 wi = glm::normalize(glm::vec3(-0.3f, 0.4f, 0.8f));
            const double Fi = fresnelReference(wi.z, 1.5);
            const auto v = eval(m, {wo}, {wi}, true);
            for (int k = 0; k < 3; ++k)
                EXPECT_NEAR(v[0][k], kColour[k] / kPi * (1 - c * F) * (1 - c * Fi), 1e-6);
        }
    }
    // Rough glass under the coat, through it from outside and back: attenuated once, at the
    // front direction, and reciprocal (f(wo, wi) / eta_o^2 = f(wi, wo) / eta_i^2).
    const MaterialCase front{"cc glass", kWhite, 0, 0.3f, 1, 1.5f, true, false, 1, -1, kWhite, 1.0f, 0.2f};
    MaterialCase plain = front;
    plain.clearcoat = 0.0f;
    const glm::vec3 a = glm::normalize(glm::vec3(0.3f, 0.1f, 0.9f)), b = glm::normalize(glm::vec3(-0.2f, 0.05f, -0.95f));
    const auto coated = eval(front, {a}, {b}, true), bare = eval(plain, {a}, {b}, true);
    const auto back = eval(front, {glm::vec3(b.x, b.y, -b.z)}, {glm::vec3(a.x, a.y, -a.z)}, false);
    const double Fa = fresnelReference(a.z, 1.5);
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(coated[0][k], bare[0][k] * (1 - Fa), 1e-5 * bare[0][k]);
        EXPECT_NEAR(coated[0][k], back[0][k] / (1.5f * 1.5f), 1e-4 * coated[0][k]);
    }
}

// A clear coat with a normal n_c of its own (bsdf.glsl clearcoatNormal): its term
// D G F / (4 cos'_o |cos_i|) is not symmetric, so light-side walks evaluate the adjoint, and
// f_adjoint(wo, wi) must equal f(wi, wo) for every pair (the lobes below the coat are symmetric
// and enter both alike); a rough coat's plain f must not be symmetric (else the test checks
// nothing). A
// smooth coat's mirror about n_c carries c F |cos_i| / |cos_o| as the adjoint instead of c F.
TEST_F(BsdfTest, ClearcoatNormalAdjoint) {
    std::mt19937 gen(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    auto upper = [&] { return glm::vec3(directionFromZPhi(u(gen), 2 * kPi * u(gen))); };
    const size_t n = 4096;
    std::vector<glm::vec3> a(n), b(n);
    for (size_t i = 0; i < n; ++i) {
        a[i] = upper();
        b[i] = upper();
    }
    int tilted = 0;
    for (const MaterialCase& m : materials()) {
        if (!m.tilted())
            continue;
        ++tilted;
        SCOPED_TRACE(m.name);
        MaterialCase adjoint = m;
        adjoint.adjoint = true;
        const auto fAdjoint = eval(adjoint, a, b, true), fSwapped = eval(m, b, a, true);
        const auto f = eval(m, a, b, true);
        size_t asymmetric = 0, nonZero = 0;
        for (size_t i = 0; i < n; ++i) {
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(fAdjoint[i][c], fSwapped[i][c], 2e-4f * std::max(fSwapped[i][c], 1.0f))
                    << "pair " << i;
            // The densities are the sampler's, the same either way.
            ASSERT_EQ(fAdjoint[i].w, f[i].w) << "pair " << i;
            nonZero += f[i].x > 0.0f ? 1 : 0;
            asymmetric += std::abs(f[i].x - fSwapped[i].x) > 0.01f * std::max(f[i].x, fSwapped[i].x);
        }
        // (A smooth coat's f has only the symmetric lobes below it; a sharp lobe few pairs.)
        if (m.clearcoatRoughness != 0.0f)
            EXPECT_GT(asymmetric, std::min<size_t>(nonZero / 10, 40)) << "the tilted coat's f should not be symmetric";

        if (m.clearcoatRoughness != 0.0f)
            continue;
        // The smooth coat's mirror: the same directions either way, weights in ratio
        // |cos_i| / |cos_o|.
        for (double cosO : {0.95, 0.25}) {
            const glm::vec3 wo = woAt(cosO);
            const auto radiance = sample(m, wo, 4096, 11), importance = sample(adjoint, wo, 4096, 11);
            int mirrors = 0;
            for (size_t i = 0; i < radiance.size(); ++i) {
                const BsdfSampleResult &r = radiance[i], &q = importance[i];
                ASSERT_EQ(r.ok(), q.ok());
                if (!r.ok() || !r.delta() || r.lobe() != LobeClearcoat)
                    continue;
                ++mirrors;
                ASSERT_EQ(r.wi, q.wi);
                ASSERT_EQ(r.pdf, q.pdf);
                for (int c = 0; c < 3; ++c)
                    ASSERT_NEAR(q.f[c], r.f[c] * r.wi.z / wo.z, 1e-5f * r.f[c] * r.wi.z / wo.z);
            }
            EXPECT_GT(mirrors, cosO > 0.5 ? 10 : -1) << "cos(theta_o) " << cosO;
        }
    }
    EXPECT_GE(tilted, 3);
}

// KHR_materials_sheen: the directional albedo E(cos) = integral of D V cos_i (Charlie D,
// Ashikhmin V) that sheenAlbedo's 8 x 16 quadrature gives the albedo scaling, against a
// 512 x 512 midpoint rule in (cos_i, phi) in double precision, at roughnesses 0.3, 0.6, 1 and
// angles from normal to grazing (within 1% where E < 1; the lobe's value is divided by E where
// E > 1, so there only the order of magnitude matters).
TEST_F(BsdfTest, SheenAlbedoQuadratureMatchesTheIntegral) {
    for (const float roughness : {0.3f, 0.6f, 1.0f}) {
        const double alpha = std::max(double(roughness) * roughness, 0.0049);
        const MaterialCase m = withSheen({"", glm::vec3(0.0f), 0, 1, 0, 1.5f, true}, "sheen", kWhite, roughness);
        for (const double cosO : {0.95, 0.6, 0.3, 0.1}) {
            const glm::dvec3 wo(std::sqrt(1 - cosO * cosO), 0.0, cosO);
            double E = 0.0;
            const int k = 512;
            for (int i = 0; i < k; ++i) {
                const double mu = (i + 0.5) / k, s = std::sqrt(1 - mu * mu);
                for (int j = 0; j < k; ++j) {
                    const double phi = 2 * kPi * (j + 0.5) / k;
                    const glm::dvec3 wi(s * std::cos(phi), s * std::sin(phi), mu);
                    const glm::dvec3 h = glm::normalize(wo + wi);
                    const double D = (2 + 1 / alpha) * std::pow(1 - h.z * h.z, 0.5 / alpha) / (2 * kPi);
                    const double V = 1 / (4 * (mu + cosO - mu * cosO));
                    E += D * V * mu * (1.0 / k) * (2 * kPi / k);
                }
            }
            const float quadrature = infoAll(m, woAt(cosO))[2].z;
            std::printf("  roughness %.1f cos %.2f: E %.4f, quadrature %.4f\n", roughness, cosO, E, quadrature);
            EXPECT_NEAR(quadrature, E, E < 1.0 ? 0.01 * E : 0.1 * E) << "roughness " << roughness << ", cos " << cosO;
        }
    }
}

// The thin sheet against the closed form of its geometric series: with R the interface's
// reflectance, the light reflected is R + T^2 R (1 + R^2 + R^4 + ...) = 2R / (1 + R) and the
// light transmitted T^2 (1 + R^2 + ...) = (1 - R) / (1 + R) (T = 1 - R; pbrt-v4
// ThinDielectricBxDF, PBR 4th ed. sec. 9.5.1), over angles from normal to grazing, seen from
// either side; the transmitted and reflected shares of bsdfSample's weight follow it (within
// their sampling error) for the smooth sheet, and within 0.5% more for a rough one of small
// alpha (roughness 0.05: alpha 0.0025).
TEST_F(BsdfTest, ThinSheetTransmittanceMatchesClosedForm) {
    for (const float ior : {1.33f, 1.5f, 2.4f}) {
        for (const bool front : {true, false}) {
            const MaterialCase smooth{"thin", kWhite, 0, 0, 1, ior, front, true};
            for (int k = 0; k < 24; ++k) {
                const double cosO = 0.01 + 0.99 * k / 23.0;
                const glm::vec3 wo = woAt(cosO);
                const double R = fresnelReference(wo.z, ior);
                const auto [p, extra] = info(smooth, wo);
                EXPECT_NEAR(extra.x, 2.0 * R / (1.0 + R), 2e-6)
                    << "ior " << ior << ", cos " << cosO << (front ? " front" : " back");
                EXPECT_EQ(extra.y, 1.0f) << "a thin sheet keeps eta";
            }
        }
        for (const auto& [roughness, tolerance] : {std::pair{0.0f, 0.0}, std::pair{0.05f, 5e-3}}) {
            const MaterialCase m{"thin", kWhite, 0, roughness, 1, ior, true, true};
            for (const double cosO : {0.95, 0.7, 0.4, 0.2}) {
                const glm::vec3 wo = woAt(cosO);
                const double R = fresnelReference(wo.z, ior);
                const uint32_t n = 1 << 16;
                const auto samples = sample(m, wo, n, 77);
                double transmitted = 0.0, reflected = 0.0;
                for (const BsdfSampleResult& s : samples) {
                    if (!s.ok())
                        continue;
                    const double w = s.f.x * std::abs(double(s.wi.z)) / s.pdf;
                    (s.wi.z < 0.0f ? transmitted : reflected) += w / n;
                }
                // Each sample carries a weight near 1, so the shares' sampling errors are
                // those of a proportion: sqrt(T (1 - T) / n) < 2e-3.
                const double sigma = std::sqrt(0.25 / n);
                EXPECT_NEAR(transmitted, (1.0 - R) / (1.0 + R), tolerance + 5.0 * sigma)
                    << "roughness " << roughness << ", ior " << ior << ", cos " << cosO;
                EXPECT_NEAR(reflected, 2.0 * R / (1.0 + R), tolerance + 5.0 * sigma)
                    << "roughness " << roughness << ", ior " << ior << ", cos " << cosO;
            }
        }
    }
}

}  // namespace
}  // namespace pmcr::test
