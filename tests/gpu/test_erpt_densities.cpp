// The densities in ERPT's Metropolis-Hastings acceptance
// (shaders/methods/energy_redistribution/path_space.glsl, mutate_lens.glsl, mutate_caustic.glsl),
// against numerical estimates, on paths the pt_record kernel records in cornell-glass:
//  - the Jacobians the target function F_nu = lum(P) Gamma carries: rasterDensity = |du/dA(x1)|,
//    reconnectionFactor / |cos_s| = |dw/dA(x2)| and the caustic Gamma / |cos_s(x1 -> x2)| =
//    |d(u, w_1) / d(A_h, w_h)| (etendue through the specular chain), each against central
//    differences of the renderer's own camera projection and specular retracing;
//  - the proposals, histogrammed in the mutation's own coordinates: the lens perturbation's
//    raster offset is uniform on its disk, the caustic perturbation's (theta, phi) are what the
//    path realises and are uniform on [0, thetaMax(x)] x [0, 2 pi) (PMC-ER's uniform law);
//  - detailed balance: for a pair x -> y of the state-dependent uniform law, the ratio of the
//    empirical proposal densities T(y -> x) / T(x -> y) (counts in equal solid-angle caps
//    around each target) matches the kernel's transitionRatio thetaMax(x) / thetaMax(y), and is
//    1 for the log-uniform law; for the lens perturbation, in the area measure of x1 (counts in
//    equal discs), it matches rasterDensity(x1) / rasterDensity(y1), what the kernel's F_nu and
//    transitionRatio of 1 amount to there.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include "distribution_test.h"
#include "gpu_test.h"
#include "methods/energy_redistribution/path_records.h"
#include "render/session.h"
#include "render_test.h"
#include "scene_builder.h"
#include "statistics.h"
#include "vk/command_batch.h"

namespace pmcr::test {
namespace {

constexpr uint32_t kMaxVertices = gpu::CHAIN_MAX_VERTICES;
constexpr int kSize = 32;  // image side of the recorded paths
constexpr uint32_t kLobeDielectric = 4;  // bsdf.glsl LOBE_DIELECTRIC
constexpr uint32_t kLobePass = 5;        // bsdf.glsl LOBE_PASS
constexpr uint32_t kLobeClearcoat = 6;   // bsdf.glsl LOBE_CLEARCOAT

struct DensityPush {
    uint32_t mode;
    uint32_t count;
    uint32_t seed;
    uint32_t k;
    glm::vec2 raster;
    float lensRadius;
    float thetaMin;
    float thetaMax;
    uint32_t uniformLaw;
    float eps;
    float epsAngle;
    uint32_t mixtureCount;  // caustic, uniform law: PMC-ER eq. 8 over the radii (0: none)
    glm::vec3 mixtureWeights;
    glm::vec3 mixtureThetas;
    uint32_t pad;
};

// A light path as a chain stores it, and where its camera sample landed.
struct ChainPath {
    std::vector<gpu::ChainVertex> vertices;
    glm::vec2 raster;
    uint32_t head = 0;  // causticHead: first non-specular vertex after x1, 0 if none
};

uint32_t causticHead(const std::vector<gpu::ChainVertex>& v) {
    if (v.size() < 2 || (v[0].flags & (gpu::VERTEX_SPECULAR | gpu::VERTEX_EMITTER)))
        return 0;
    for (uint32_t i = 1; i < v.size(); ++i)
        if (!(v[i].flags & gpu::VERTEX_SPECULAR))
            return (v[i].flags & gpu::VERTEX_ENVIRONMENT) ? 0 : i;  // (no directional lights here)
    return 0;
}

// cornell-glass with a point light beside its area light (the caustic Gamma at a point head).
Scene cornellGlassWithPointLight() {
    Scene s = testScene("scenes/cornell-glass.glb");
    const glm::vec3 size = s.boundsMax - s.boundsMin;
    gpu::PunctualLight l{};
    l.type = gpu::PUNCTUAL_POINT;
    l.position = s.boundsMin + size * glm::vec3(0.3f, 0.85f, 0.55f);
    l.direction = glm::vec3(0, -1, 0);
    l.intensity = glm::vec3(glm::dot(size, size));
    s.punctualLights = {l};
    s.path = "cornell-glass-point-light.glb";
    finalizeScene(s);
    return s;
}

// cornell-glass with its glass material given `flags` (thin-walled, BLEND) and `coverage`.
Scene cornellGlassAs(uint32_t flags, float coverage, const char* name) {
    Scene s = testScene("scenes/cornell-glass.glb");
    int changed = 0;
    for (gpu::Material& m : s.materials) {
        if (m.transmission <= 0.0f) continue;
        m.flags |= flags;
        m.coverage = coverage;
        ++changed;
    }
    EXPECT_GE(changed, 1) << "cornell-glass has a glass material";
    s.path = name;
    finalizeScene(s);
    return s;
}

// cornell-glass with every opaque surface under a smooth clear coat (KHR_materials_clearcoat)
// whose clearcoatNormalTexture tilts the coat's normal by 30 degrees along the tangent: caustic
// chains reflect off the coat about that normal, not the shading normal.
Scene cornellGlassTiltedCoat() {
    Scene s = testScene("scenes/cornell-glass.glb");
    s.textures.push_back(normalTexel("coat-normal", glm::vec3(0.5f, 0.0f, 0.866f)));
    int coated = 0;
    for (gpu::Material& m : s.materials) {
        if (m.transmission > 0.0f || m.emission != glm::vec3(0.0f)) continue;
        m.clearcoat = 1.0f;
        m.clearcoatRoughness = 0.0f;
        m.clearcoatNormalTexture = uint32_t(s.textures.size());
        m.clearcoatNormalScale = 1.0f;
        ++coated;
    }
    EXPECT_GE(coated, 4) << "cornell-glass has walls";
    setPlanarTangents(s);  // the walls are flat; the sphere is glass, uncoated
    s.path = "cornell-tilted-coat.glb";
    finalizeScene(s);
    EXPECT_EQ(sceneFeatures(s) & gpu::SCENE_FEATURE_NO_CLEARCOAT_NORMALS, 0u);
    return s;
}

class ErptDensities : public GpuTest {
protected:
    void SetUp() override {
        GpuTest::SetUp();
        RenderSettings settings;
        settings.width = kSize;
        settings.height = kSize;
        m_session = std::make_unique<RenderSession>(
            context(), testScene("scenes/cornell-glass.glb"), settings, kSize, kSize);
    }
    void TearDown() override {
        m_session.reset();
        m_scene.reset();
        GpuTest::TearDown();
    }

    // Renders `scene` from now on (recordPaths then uses the kernel for its lights).
    void useScene(Scene scene) {
        m_session.reset();
        m_scene = std::make_unique<Scene>(std::move(scene));
        RenderSettings settings;
        settings.width = kSize;
        settings.height = kSize;
        m_session = std::make_unique<RenderSession>(context(), *m_scene, settings, kSize, kSize);
        m_recordKernel = "methods/pt/pt_record_all_lights";
    }

    // Light paths of `passes` path-traced samples per pixel, split as erpt_seed.comp splits
    // them (every implicit and explicit path of a record with a non-zero contribution).
    std::vector<ChainPath> recordPaths(uint32_t passes) {
        const uint32_t pixels = kSize * kSize;
        vk::Kernel ptRecord(m_session->layout(), m_recordKernel);
        PathRecords recorded(context(), pixels, "test path");
        vk::DescriptorSet work(m_session->layout(), vk::DescriptorSet::Kind::Work, "record work");
        recorded.bindTracer(work, *m_session, m_session->placeholder());
        gpu::PtPush push{};
        push.source = gpu::PT_SOURCE_TILE;
        push.flags = gpu::PT_FLAG_DEPOSIT;
        push.invocationCount = pixels;
        push.samplesPerPixel = 1;
        push.seed = 23;
        push.maxDepth = 8;
        push.rrDepth = 3;
        std::vector<ChainPath> paths;
        for (uint32_t pass = 0; pass < passes; ++pass) {
            push.sampleBase = pass;
            vk::CommandBatch batch(m_session->layout());
            batch.bind(m_session->scene().descriptorSet());
            batch.bind(work);
            batch.dispatch(ptRecord, push, pixels);
            batch.submitAndWait();
            const auto recs = recorded.records().download<gpu::PathRecord>(pixels);
            const auto verts = recorded.vertices().download<gpu::PathVertex>(pixels * gpu::PATH_MAX_VERTICES);
            for (const gpu::PathRecord& r : recs) {
                for (uint32_t j = 0; j < r.vertexCount; ++j) {
                    for (int kind = 0; kind < 2; ++kind) {
                        const gpu::PathVertex& end = verts[r.firstVertex + j];
                        const glm::vec3 c =
                            kind == 0 ? end.implicitContribution : end.explicitContribution;
                        const bool has = kind == 0
                                             ? (end.flags & gpu::VERTEX_EMITTER) != 0
                                             : (end.flags & gpu::VERTEX_HAS_LIGHT_SAMPLE) != 0;
                        if (!has || !(c.x + c.y + c.z > 0.0f))
                            continue;
                        ChainPath p;
                        p.raster = r.raster;
                        for (uint32_t v = 0; v <= j; ++v) {
                            const gpu::PathVertex& pv = verts[r.firstVertex + v];
                            uint32_t flags = 0;
                            if (v < j) {
                                flags =
                                    pv.flags & (gpu::VERTEX_SPECULAR | gpu::VERTEX_TRANSMISSION);
                                if (pv.flags & gpu::VERTEX_SPECULAR)
                                    flags |= pv.lobe << gpu::CHAIN_LOBE_SHIFT;
                            } else if (kind == 0) {
                                flags = gpu::VERTEX_EMITTER | (pv.flags & gpu::VERTEX_ENVIRONMENT);
                            }
                            p.vertices.push_back(
                                {pv.triangle, pv.barycentrics.x, pv.barycentrics.y, flags});
                        }
                        if (kind == 1) {
                            uint32_t flags = gpu::VERTEX_EMITTER;
                            if (end.flags & gpu::VERTEX_SAMPLED_PUNCTUAL) flags |= gpu::VERTEX_PUNCTUAL;
                            if (end.flags & gpu::VERTEX_SAMPLED_ENVIRONMENT) flags |= gpu::VERTEX_ENVIRONMENT;
                            p.vertices.push_back({end.lightTriangle, end.lightB1, end.lightB2, flags});
                        }
                        p.head = causticHead(p.vertices);
                        paths.push_back(p);
                    }
                }
            }
        }
        return paths;
    }

    // Runs the density test kernel: `count` invocations, paths in `chain` (binding 5).
    std::vector<glm::vec4> call(const DensityPush& push, size_t resultCount,
                                const vk::Buffer& chain, const std::vector<gpu::ChainVertex>& templ,
                                const std::vector<glm::uvec2>& info) {
        auto results = zeros(resultCount * sizeof(glm::vec4), "density results");
        std::vector<gpu::ChainVertex> t = templ;
        t.resize(std::max<size_t>(t.size(), 1));
        std::vector<glm::uvec2> in = info;
        in.resize(std::max<size_t>(in.size(), 1));
        auto templBuffer = storage(t, "template path");
        auto infoBuffer = storage(in, "path info");
        run("tests/erpt_density_test", push, push.count,
            {&results, &templBuffer, &infoBuffer, nullptr, nullptr, &chain},
            &m_session->scene().descriptorSet());
        return results.download<glm::vec4>(resultCount);
    }

    // Proposals from `path` (modes 0 and 1), and the chain buffer holding each proposal y.
    std::vector<glm::vec4> propose(uint32_t mode, const ChainPath& path, uint32_t count,
                                   uint32_t seed, DensityPush push, vk::Buffer& chain) {
        push.mode = mode;
        push.count = count;
        push.seed = seed;
        push.k = uint32_t(path.vertices.size());
        push.raster = path.raster;
        return call(push, size_t(4) * count, chain, path.vertices, {});
    }

    // Proposal `pick` of a propose() call of n proposals from x: the path y it left in `chain`.
    ChainPath proposal(const ChainPath& x, vk::Buffer& chain, uint32_t n, uint32_t pick,
                       const std::vector<glm::vec4>& proposals) {
        ChainPath y = x;
        const auto slots = chain.download<gpu::ChainVertex>(size_t(n) * 2 * kMaxVertices);
        for (size_t v = 0; v < y.vertices.size(); ++v)
            y.vertices[v] = slots[(size_t(pick) * 2 + 1) * kMaxVertices + v];
        y.raster = glm::vec2(proposals[4 * pick]);
        return y;
    }

    // Valid proposals from `from` for which near(result record) holds, over `batches` batches
    // of n (seeds seed, seed + 1, ...).
    template <typename Near>
    double countProposals(uint32_t mode, const ChainPath& from, uint32_t n, uint32_t seed,
                          int batches, const DensityPush& push, vk::Buffer& chain, Near near) {
        double hits = 0.0;
        for (int b = 0; b < batches; ++b) {
            const auto r = propose(mode, from, n, seed + uint32_t(b), push, chain);
            for (uint32_t i = 0; i < n; ++i)
                if (r[4 * i].z > 0.5f && near(&r[4 * i]))
                    hits += 1.0;
        }
        return hits;
    }

    vk::Buffer chainBuffer(uint32_t chains) {
        return zeros(size_t(chains) * 2 * kMaxVertices * sizeof(gpu::ChainVertex),
                     "chain vertices");
    }

    // Detailed balance of the caustic perturbation on a recorded path (defined below).
    void expectCausticDetailedBalance(bool uniformLaw);
    // The Jacobians against finite differences on the current scene's paths (defined below).
    void expectJacobiansMatchFiniteDifferences(uint32_t lobe, bool transmits = true);

    std::unique_ptr<Scene> m_scene;  // useScene's
    std::unique_ptr<RenderSession> m_session;
    std::string m_recordKernel = "methods/pt/pt_record";
};

glm::dvec3 dv(const glm::vec4& v) {
    return glm::dvec3(v.x, v.y, v.z);
}

void basis(const glm::dvec3& n, glm::dvec3& t, glm::dvec3& b) {
    const glm::dvec3 a = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    t = glm::normalize(glm::cross(n, a));
    b = glm::cross(n, t);
}

double det2(double a, double b, double c, double d) {
    return a * d - b * c;
}

double det4(double m[4][4]) {
    double a[4][4];
    std::copy(&m[0][0], &m[0][0] + 16, &a[0][0]);
    double det = 1.0;
    for (int c = 0; c < 4; ++c) {
        int p = c;
        for (int r = c + 1; r < 4; ++r)
            if (std::abs(a[r][c]) > std::abs(a[p][c]))
                p = r;
        if (a[p][c] == 0.0)
            return 0.0;
        if (p != c) {
            for (int k = 0; k < 4; ++k)
                std::swap(a[p][k], a[c][k]);
            det = -det;
        }
        det *= a[c][c];
        for (int r = c + 1; r < 4; ++r) {
            const double f = a[r][c] / a[c][c];
            for (int k = c; k < 4; ++k)
                a[r][k] -= f * a[c][k];
        }
    }
    return det;
}

// Finite-difference Jacobians of one path (mode 2 output at o).
struct Jacobians {
    double rasterDensity, reconnection, cosS12, causticGamma;  // the kernel's
    double rasterFd, solidAngleFd, causticFd;                  // the numerical estimates
    bool causticValid = false;
};

Jacobians jacobians(const std::vector<glm::vec4>& r, size_t o, bool caustic) {
    Jacobians j{};
    j.rasterDensity = r[o].x;
    j.reconnection = r[o].y;
    j.cosS12 = r[o].z;
    j.causticGamma = r[o].w;
    const double eps = r[o + 1].z, epsAngle = r[o + 1].w;
    auto d = [&](size_t a, size_t b) {
        return (glm::dvec2(r[a]) - glm::dvec2(r[b])) / (2.0 * eps);
    };
    const glm::dvec2 u1 = d(o + 2, o + 3), u2 = d(o + 4, o + 5);
    j.rasterFd = std::abs(det2(u1.x, u2.x, u1.y, u2.y));
    glm::dvec3 t, b;
    basis(glm::normalize(dv(r[o + 6]) + dv(r[o + 7])), t, b);
    const glm::dvec3 w1 = (dv(r[o + 6]) - dv(r[o + 7])) / (2.0 * eps);
    const glm::dvec3 w2 = (dv(r[o + 8]) - dv(r[o + 9])) / (2.0 * eps);
    j.solidAngleFd =
        std::abs(det2(glm::dot(w1, t), glm::dot(w2, t), glm::dot(w1, b), glm::dot(w2, b)));
    if (!caustic)
        return j;
    j.causticValid = true;
    for (int m = 0; m < 9; ++m)
        j.causticValid = j.causticValid && r[o + 10 + 2 * m].z > 0.5f;
    if (!j.causticValid)
        return j;
    basis(glm::normalize(dv(r[o + 11 + 16])), t, b);
    // Columns: head position along its two tangents (step eps), head direction turned towards
    // its two basis vectors (normalize(w + s e epsAngle) is at angle atan(epsAngle)).
    double m[4][4];
    for (int c = 0; c < 4; ++c) {
        const size_t plus = o + 10 + 2 * (2 * c), minus = plus + 2;
        const double step = 2.0 * (c < 2 ? eps : std::atan(double(epsAngle)));
        const glm::dvec2 du = (glm::dvec2(r[plus]) - glm::dvec2(r[minus])) / step;
        const glm::dvec3 dw = (dv(r[plus + 1]) - dv(r[minus + 1])) / step;
        m[0][c] = du.x;
        m[1][c] = du.y;
        m[2][c] = glm::dot(dw, t);
        m[3][c] = glm::dot(dw, b);
    }
    j.causticFd = std::abs(det4(m));
    return j;
}

// rasterDensity, reconnectionFactor and the caustic Gamma against central differences, at two
// step sizes: a path whose two estimates disagree by more than 1% is too curved (near a caustic's
// fold, or a ray grazing an edge) for the step and is left out; most must remain.
TEST_F(ErptDensities, JacobiansMatchFiniteDifferences) { expectJacobiansMatchFiniteDifferences(0); }

// The same through a thin sheet (thin-walled transmission: cornell-glass's sphere as a smooth
// thin dielectric): its transmission is a specular vertex of eta 1, straight through, whose
// etendue factor bsdfLobeEta gives; the chains cross the sphere's two walls.
TEST_F(ErptDensities, JacobiansThroughThinGlassMatchFiniteDifferences) {
    useScene(cornellGlassAs(gpu::MATERIAL_THIN_WALLED, 1.0f, "cornell-thin-glass.glb"));
    expectJacobiansMatchFiniteDifferences(kLobeDielectric);
}

// And through a BLEND pass: the sphere as glass of coverage 0.5, whose pass-through is a
// specular transmission of eta 1 beside the glass's own refraction (eta 1.5).
TEST_F(ErptDensities, JacobiansThroughBlendCoverageMatchFiniteDifferences) {
    useScene(cornellGlassAs(gpu::MATERIAL_BLEND, 0.5f, "cornell-blend-glass.glb"));
    expectJacobiansMatchFiniteDifferences(kLobePass);
}

// And off a smooth clear coat whose normal is not the shading normal (a normal texture of its
// own): the caustic Gamma takes the coat's normal at its mirror vertices.
TEST_F(ErptDensities, JacobiansOffATiltedClearcoatMatchFiniteDifferences) {
    useScene(cornellGlassTiltedCoat());
    expectJacobiansMatchFiniteDifferences(kLobeClearcoat, false);
}

// `lobe` (bsdf.glsl LOBE_*; 0: any): the checked chains must cross that lobe's specular
// transmission (`transmits`) or reflection.
void ErptDensities::expectJacobiansMatchFiniteDifferences(uint32_t lobe, bool transmits) {
    // Whether the path scatters by `lobe` (transmitting or reflecting) at a specular vertex.
    auto crosses = [&](const ChainPath& p) {
        if (lobe == 0) return true;
        for (const gpu::ChainVertex& v : p.vertices) {
            const uint32_t want = gpu::VERTEX_SPECULAR | (transmits ? gpu::VERTEX_TRANSMISSION : 0u);
            if ((v.flags & (gpu::VERTEX_SPECULAR | gpu::VERTEX_TRANSMISSION)) == want &&
                ((v.flags >> gpu::CHAIN_LOBE_SHIFT) & 15u) == lobe)
                return true;
        }
        return false;
    };
    std::vector<ChainPath> all = recordPaths(4);
    std::vector<ChainPath> paths;
    int withChain = 0;
    for (const ChainPath& p : all) {
        if (p.vertices[0].flags & gpu::VERTEX_SPECULAR)
            continue;
        // Half of them through a specular chain (h > 1) where the scene has them; reflections
        // off `lobe` are rarer than the glass's chains and are picked out.
        if (p.head > 1 && (transmits || crosses(p)) && withChain < 128) {
            paths.push_back(p);
            ++withChain;
        } else if (paths.size() < size_t(128 + withChain)) {
            paths.push_back(p);
        }
    }
    ASSERT_GE(withChain, 16) << "cornell-glass should give caustic paths through its glass";
    const uint32_t n = uint32_t(paths.size());
    std::vector<gpu::ChainVertex> packed(size_t(n) * 2 * kMaxVertices);
    std::vector<glm::uvec2> info(n);
    for (uint32_t j = 0; j < n; ++j) {
        std::copy(paths[j].vertices.begin(), paths[j].vertices.end(),
                  packed.begin() + size_t(j) * 2 * kMaxVertices);
        info[j] = {uint32_t(paths[j].vertices.size()), paths[j].head};
    }
    auto chain = storage(packed, "paths");
    const Scene& scene = m_scene ? *m_scene : testScene("scenes/cornell-glass.glb");
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (const auto& v : scene.vertices) {
        lo = glm::min(lo, v.position);
        hi = glm::max(hi, v.position);
    }
    const float extent = glm::length(hi - lo);
    DensityPush push{};
    push.mode = 2;
    push.count = n;
    std::vector<Jacobians> at[2];
    for (int s = 0; s < 2; ++s) {
        push.eps = extent * (s == 0 ? 2e-4f : 1e-4f);
        push.epsAngle = (s == 0 ? 2e-4f : 1e-4f);
        const auto r = call(push, size_t(64) * n, chain, {}, info);
        for (uint32_t j = 0; j < n; ++j)
            at[s].push_back(jacobians(r, size_t(64) * j, paths[j].head > 0));
    }
    auto agree = [](double a, double b, double tol) {
        return std::abs(a - b) <= tol * std::max(std::abs(a), std::abs(b));
    };
    int rasterChecked = 0, solidChecked = 0, causticChecked = 0, causticChainChecked = 0;
    double worstRaster = 0.0, worstSolid = 0.0, worstCaustic = 0.0;
    for (uint32_t j = 0; j < n; ++j) {
        const Jacobians& a = at[0][j];
        const Jacobians& b = at[1][j];
        if (agree(a.rasterFd, b.rasterFd, 0.01)) {
            ++rasterChecked;
            worstRaster = std::max(worstRaster, std::abs(b.rasterDensity / b.rasterFd - 1.0));
            EXPECT_NEAR(b.rasterDensity / b.rasterFd, 1.0, 0.02) << "rasterDensity, path " << j;
        }
        if (b.cosS12 > 0.05 && agree(a.solidAngleFd, b.solidAngleFd, 0.01)) {
            ++solidChecked;
            const double ratio = b.reconnection / b.cosS12 / b.solidAngleFd;
            worstSolid = std::max(worstSolid, std::abs(ratio - 1.0));
            EXPECT_NEAR(ratio, 1.0, 0.02) << "reconnectionFactor / |cos_s|, path " << j;
        }
        // Through a glass sphere the float noise of single differences reaches a few tenths of a
        // percent: only paths whose two estimates agree within 0.3% are compared. The float
        // rounding of the chain's own Jacobian takes the worst ratio to 1.9% on lavapipe and
        // 2.6% on an NVIDIA H200 (whose compiler fuses multiply-adds), hence 3%.
        if (a.causticValid && b.causticValid && b.cosS12 > 0.05 &&
            agree(a.causticFd, b.causticFd, 0.003)) {
            ++causticChecked;
            if (paths[j].head > 1 && crosses(paths[j]))
                ++causticChainChecked;
            const double ratio = b.causticGamma / b.cosS12 / b.causticFd;
            worstCaustic = std::max(worstCaustic, std::abs(ratio - 1.0));
            EXPECT_NEAR(ratio, 1.0, 0.03)
                << "causticGamma / |cos_s(x1 -> x2)|, path " << j << " (head " << paths[j].head
                << " of " << paths[j].vertices.size() << ")";
        }
    }
    std::printf(
        "  checked %d rasterDensity (worst %.2e), %d reconnection (worst %.2e), %d caustic Gamma "
        "(%d through specular chains; worst %.2e) of %u paths\n",
        rasterChecked, worstRaster, solidChecked, worstSolid, causticChecked, causticChainChecked,
        worstCaustic, n);
    EXPECT_GE(rasterChecked, int(n) * 3 / 4);
    EXPECT_GE(solidChecked, int(n) / 2);
    EXPECT_GE(causticChainChecked, 24);
}

// The lens perturbation's raster offsets, all proposals included (the raster move is drawn before
// any tracing): uniform on the disk of lensRadius pixels (equal-area cells in r^2 and angle),
// which makes T(x -> y) = T(y -> x) in raster measure, the kernel's transitionRatio of 1.
TEST_F(ErptDensities, LensProposalsAreUniformOnTheDisk) {
    std::vector<ChainPath> all = recordPaths(1);
    const ChainPath* x = nullptr;
    for (const ChainPath& p : all)
        if (!(p.vertices[0].flags & gpu::VERTEX_SPECULAR) && p.vertices.size() >= 2 &&
            p.raster.x > 8 && p.raster.x < kSize - 8 && p.raster.y > 8 && p.raster.y < kSize - 8) {
            x = &p;
            break;
        }
    ASSERT_NE(x, nullptr);
    const uint32_t n = 1 << 16;
    auto chain = chainBuffer(n);
    DensityPush push{};
    push.lensRadius = 4.0f;
    push.thetaMin = 1e-4f;
    push.thetaMax = 0.1f;
    const auto r = propose(0, *x, n, 5, push, chain);
    const int rings = 8, sectors = 16;
    std::vector<double> observed(rings * sectors, 0.0);
    int valid = 0;
    for (uint32_t i = 0; i < n; ++i) {
        const glm::dvec2 d =
            (glm::dvec2(r[4 * i]) - glm::dvec2(x->raster)) / double(push.lensRadius);
        const double r2 = glm::dot(d, d);
        ASSERT_LE(r2, 1.0 + 1e-4) << "proposal " << i << " outside the disk";
        double phi = std::atan2(d.y, d.x);
        if (phi < 0.0)
            phi += 2.0 * std::numbers::pi;
        const int a = std::min(rings - 1, int(r2 * rings));
        const int b = std::min(sectors - 1, int(phi / (2.0 * std::numbers::pi) * sectors));
        observed[a * sectors + b] += 1.0;
        if (r[4 * i].z > 0.5f) {
            ++valid;
            ASSERT_EQ(r[4 * i].w, 1.0f) << "lens transitionRatio";
        }
    }
    EXPECT_GT(valid, int(n) / 4);
    const std::vector<double> expected(rings * sectors, double(n) / (rings * sectors));
    std::printf("  lens raster offsets: %s\n", chi2Test(observed, expected).describe().c_str());
    EXPECT_TRUE(chi2Passes(observed, expected, "lens raster offsets on the disk"));
}

// At least a pixel inside the image (the discs counted below reach 0.75 pixels around a point).
bool insideByAPixel(const glm::vec2& raster) {
    return raster.x >= 1.0f && raster.y >= 1.0f && raster.x <= kSize - 1.0f &&
           raster.y <= kSize - 1.0f;
}

// Distance from a point in a triangle's plane to the triangle's nearest edge.
double edgeDistance(const Scene& scene, uint32_t tri, const glm::dvec3& p) {
    const gpu::Triangle& t = scene.triangles[tri];
    const glm::dvec3 v[3] = {glm::dvec3(scene.vertices[t.i0].position),
                             glm::dvec3(scene.vertices[t.i1].position),
                             glm::dvec3(scene.vertices[t.i2].position)};
    double d = 1e30;
    for (int e = 0; e < 3; ++e) {
        const glm::dvec3 a = v[e], ab = v[(e + 1) % 3] - a;
        const double s = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
        d = std::min(d, glm::length(p - (a + s * ab)));
    }
    return d;
}

// Detailed balance of the lens perturbation in the area measure of x1, where it is not trivial:
// T_A(x -> y) = rasterDensity(y1) / (pi r^2), so the kernel's F_nu and transitionRatio of 1
// amount to T_A(y -> x) / T_A(x -> y) = rasterDensity(x1) / rasterDensity(y1). For an E D L path
// on cornell-glass's floor and a proposal y whose rasterDensity differs most from x's, count the
// proposals from each landing within the same world distance of the other's x1 (discs of equal
// area on the plane): n(y -> near x1) / n(x -> near y1) estimates that ratio.
TEST_F(ErptDensities, LensDetailedBalanceInAreaMeasure) {
    std::vector<ChainPath> all = recordPaths(1);
    const uint32_t n = 1 << 16;
    auto chain = chainBuffer(n);
    DensityPush push{};
    push.lensRadius = 4.0f;
    push.thetaMin = 1e-4f;
    push.thetaMax = 0.1f;
    // x among 64 E D L paths spread over the image, and y among its valid proposals 1.5 to 3
    // pixels away on the same triangle, both a pixel inside the image, both farther from its edges
    // than half their distance (so the discs counted below lie on that plane): the largest density
    // change.
    const ChainPath* x = nullptr;
    int pick = -1;
    double pickLog = 0.0;
    int tried = 0;
    const uint32_t kSelect = 4096;
    const Scene& scene = testScene("scenes/cornell-glass.glb");
    const size_t stride = std::max<size_t>(1, all.size() / 64);
    for (size_t c = 0; c < all.size(); c += stride) {
        const ChainPath& p = all[c];
        if (p.vertices.size() != 2 || (p.vertices[0].flags & gpu::VERTEX_SPECULAR) ||
            !insideByAPixel(p.raster))
            continue;
        if (++tried > 64)
            break;
        const auto r = propose(0, p, kSelect, 41, push, chain);
        for (uint32_t i = 0; i < kSelect; ++i) {
            const double d = glm::length(glm::dvec2(r[4 * i]) - glm::dvec2(p.raster));
            if (r[4 * i].z < 0.5f || d < 1.5 || d > 3.0 || !insideByAPixel(glm::vec2(r[4 * i])) ||
                uint32_t(r[4 * i + 3].w) != p.vertices[0].triangle)
                continue;
            const glm::dvec3 a = dv(r[4 * i + 3]);
            const glm::dvec3 b(r[4 * i + 1].z, r[4 * i + 1].w, r[4 * i + 2].x);
            const uint32_t tri = p.vertices[0].triangle;
            if (std::min(edgeDistance(scene, tri, a), edgeDistance(scene, tri, b)) <
                0.5 * glm::length(a - b))
                continue;
            const double l = std::abs(std::log(double(r[4 * i + 2].y) / r[4 * i + 2].z));
            if (pick < 0 || l > pickLog) {
                x = &p;
                pick = int(i);
                pickLog = l;
            }
        }
    }
    ASSERT_NE(x, nullptr);
    // x's proposals again, to read y from the chain buffer.
    const auto first = propose(0, *x, n, 41, push, chain);
    const ChainPath y = proposal(*x, chain, n, pick, first);
    const glm::dvec3 y1(first[4 * pick + 1].z, first[4 * pick + 1].w, first[4 * pick + 2].x);
    const glm::dvec3 x1 = dv(first[4 * pick + 3]);
    const double densityX = first[4 * pick + 2].z, densityY = first[4 * pick + 2].y;
    const double claimed = densityX / densityY;  // T_A(y -> x) / T_A(x -> y)
    const double rho = 0.25 * glm::length(y1 - x1);
    const uint32_t plane = x->vertices[0].triangle;
    auto countNear = [&](const ChainPath& from, const glm::dvec3& target, uint32_t seed,
                         int batches) {
        return countProposals(0, from, n, seed, batches, push, chain, [&](const glm::vec4* r) {
            const glm::dvec3 p(r[1].z, r[1].w, r[2].x);
            return uint32_t(r[3].w) == plane && glm::length(p - target) < rho;
        });
    };
    const int batches = 8;
    const double nxy = countNear(*x, y1, 100, batches);
    const double nyx = countNear(y, x1, 200, batches);
    ASSERT_GT(nxy, 100.0);
    ASSERT_GT(nyx, 100.0);
    const double empirical = nyx / nxy;
    const double relErr = std::sqrt(1.0 / nxy + 1.0 / nyx);
    std::printf(
        "  lens: rasterDensity(x1) %.4g, rasterDensity(y1) %.4g; T_A(y->x)/T_A(x->y) "
        "empirical %.4f +- %.4f, kernel %.4f\n",
        densityX, densityY, empirical, empirical * relErr, claimed);
    EXPECT_NEAR(std::log(empirical), std::log(claimed), 4.0 * relErr);
}

// Solid angle of a cap of angular radius rho.
double capSolidAngle(double rho) {
    return 2.0 * std::numbers::pi * (1.0 - std::cos(rho));
}

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
    return 2.0 * std::asin(std::min(1.0, glm::length(a - b) / 2.0));
}

// A caustic path through cornell-glass's glass (x1 diffuse, then specular vertices).
std::optional<ChainPath> causticPath(const std::vector<ChainPath>& all) {
    const ChainPath* best = nullptr;
    for (const ChainPath& p : all)
        if (p.head > 1 && p.raster.x > 4 && p.raster.x < kSize - 4 && p.raster.y > 4 &&
            p.raster.y < kSize - 4 && (!best || p.vertices.size() < best->vertices.size()))
            best = &p;
    return best ? std::optional<ChainPath>(*best) : std::nullopt;
}

// The caustic perturbation with PMC-ER's uniform law: every valid proposal y is x's head
// direction turned by the (theta, phi) drawn, theta uniform on [0, thetaMax(x)] and phi on
// [0, 2 pi) (chi-square over all proposals), no valid y has theta > thetaMax(y) (the reverse move
// must be possible), and the kernel's transitionRatio is thetaMax(x) / thetaMax(y).
TEST_F(ErptDensities, CausticProposalsRealiseTheirAngles) {
    const std::optional<ChainPath> x = causticPath(recordPaths(4));
    ASSERT_TRUE(x) << "no caustic path recorded";
    const uint32_t n = 1 << 16;
    auto chain = chainBuffer(n);
    DensityPush push{};
    push.thetaMin = 1e-4f;
    push.thetaMax = 0.02f;  // theta(d) of the uniform law, scaled per path by causticThetaMax
    push.uniformLaw = 1;
    const auto r = propose(1, *x, n, 9, push, chain);
    const double thetaMaxX = r[1].z;
    ASSERT_GT(thetaMaxX, 0.0);
    const int thetaCells = 16, phiCells = 8;
    std::vector<double> observed(thetaCells * phiCells, 0.0);
    int valid = 0;
    double worstTheta = 0.0;
    for (uint32_t i = 0; i < n; ++i) {
        const double theta = r[4 * i + 1].x, phi = r[4 * i + 1].y;
        ASSERT_EQ(r[4 * i + 1].z, float(thetaMaxX));
        const int a = std::min(thetaCells - 1, int(theta / thetaMaxX * thetaCells));
        const int b = std::min(phiCells - 1, int(phi / (2.0 * std::numbers::pi) * phiCells));
        observed[a * phiCells + b] += 1.0;
        if (r[4 * i].z < 0.5f)
            continue;
        ++valid;
        const glm::dvec3 toY = dv(r[4 * i + 2]), toX = dv(r[4 * i + 3]);
        const double measured = angleBetween(toY, toX);
        worstTheta = std::max(worstTheta, std::abs(measured - theta) / thetaMaxX);
        ASSERT_NEAR(measured, theta, 1e-3 * thetaMaxX) << "proposal " << i;
        const double thetaMaxY = r[4 * i + 1].w;
        ASSERT_LE(theta, thetaMaxY);
        ASSERT_NEAR(r[4 * i].w, thetaMaxX / thetaMaxY, 1e-5 * thetaMaxX / thetaMaxY);
    }
    std::printf(
        "  %d of %u caustic proposals valid; thetaMax(x) %.4g; worst |theta measured - drawn| "
        "%.2e thetaMax\n",
        valid, n, thetaMaxX, worstTheta);
    EXPECT_GT(valid, int(n) / 10);
    const std::vector<double> expected(thetaCells * phiCells, double(n) / (thetaCells * phiCells));
    std::printf("  caustic (theta, phi): %s\n", chi2Test(observed, expected).describe().c_str());
    EXPECT_TRUE(chi2Passes(observed, expected, "caustic (theta, phi), uniform law"));
}

// Detailed balance of the state-dependent uniform law: for x and a valid proposal y from it whose
// thetaMax differs most from x's, propose many times from each and count the valid proposals in
// caps of equal solid angle around the other: n(y -> near x) / n(x -> near y) estimates
// T(y -> x) / T(x -> y), which the kernel claims is transitionRatio(x -> y) = thetaMax(x) /
// thetaMax(y). (The density varies over a cap, the same way for both counts, so it cancels.)
void ErptDensities::expectCausticDetailedBalance(bool uniformLaw) {
    const std::optional<ChainPath> x = causticPath(recordPaths(4));
    ASSERT_TRUE(x) << "no caustic path recorded";
    const uint32_t n = 1 << 16;
    auto chain = chainBuffer(n);
    DensityPush push{};
    push.thetaMin = 1e-4f;
    push.thetaMax = 0.05f;
    push.uniformLaw = uniformLaw ? 1 : 0;
    const auto first = propose(1, *x, n, 31, push, chain);
    const double thetaMaxX = uniformLaw ? first[1].z : push.thetaMax;
    // The pair: theta in the middle of both ranges, thetaMax(y) as far from thetaMax(x) as found
    // (the log-uniform law has a fixed range).
    int pick = -1;
    double pickLog = 0.0;
    for (uint32_t i = 0; i < n; ++i) {
        if (first[4 * i].z < 0.5f)
            continue;
        const double theta = first[4 * i + 1].x;
        const double thetaMaxY = uniformLaw ? first[4 * i + 1].w : thetaMaxX;
        if (theta < 0.4 * std::min(thetaMaxX, thetaMaxY) ||
            theta > 0.6 * std::min(thetaMaxX, thetaMaxY))
            continue;
        const double l = std::abs(std::log(thetaMaxY / thetaMaxX));
        if (pick < 0 || l > pickLog) {
            pick = int(i);
            pickLog = l;
        }
    }
    ASSERT_GE(pick, 0);
    const ChainPath y = proposal(*x, chain, n, uint32_t(pick), first);
    const double claimed = first[4 * pick].w;  // T(y -> x) / T(x -> y)
    const glm::dvec3 omegaX = dv(first[4 * pick + 3]), omegaY = dv(first[4 * pick + 2]);
    const double rho = 0.25 * angleBetween(omegaX, omegaY);

    // Counts of valid proposals within rho of `target`, over `batches` batches of n.
    auto countNear = [&](const ChainPath& from, const glm::dvec3& target, uint32_t seed,
                         int batches) {
        return countProposals(1, from, n, seed, batches, push, chain, [&](const glm::vec4* r) {
            return angleBetween(dv(r[2]), target) < rho;
        });
    };
    const int batches = 8;
    const double nxy = countNear(*x, omegaY, 1000, batches);
    const double nyx = countNear(y, omegaX, 2000, batches);
    ASSERT_GT(nxy, 100.0);
    ASSERT_GT(nyx, 100.0);
    const double empirical = nyx / nxy;
    const double relErr = std::sqrt(1.0 / nxy + 1.0 / nyx);
    const double omega = capSolidAngle(rho), total = double(batches) * n;
    std::printf(
        "  %s law: thetaMax(x) %.4g, thetaMax(y) %.4g; T(x->y) %.4g, T(y->x) %.4g per sr (caps of "
        "%.3g "
        "sr); "
        "T(y->x)/T(x->y) empirical %.4f +- %.4f, kernel %.4f\n",
        uniformLaw ? "uniform" : "log-uniform", thetaMaxX, thetaMaxX / claimed,
        nxy / (total * omega), nyx / (total * omega), omega, empirical, empirical * relErr,
        claimed);
    EXPECT_NEAR(std::log(empirical), std::log(claimed), 4.0 * relErr);
}

TEST_F(ErptDensities, CausticDetailedBalanceMatchesEmpiricalDensities) {
    expectCausticDetailedBalance(true);
}

// ERPT's own law, log-uniform in [thetaMin, thetaMax]: symmetric, transitionRatio 1.
TEST_F(ErptDensities, CausticLogUniformLawIsSymmetric) {
    expectCausticDetailedBalance(false);
}

}  // namespace
}  // namespace pmcr::test

namespace pmcr::test {
namespace {

// PMC-ER's full-mixture acceptance (eq. 8) over the radii of the caustic perturbation's uniform
// law: the angle is drawn from component j with probability alpha_j, uniform on
// [0, thetaMax_j(x)] with thetaMax_j(x) = theta(d_j) c(x) (c the path's scale, eq. 6), so the
// density in theta is p_x(theta) = sum_j alpha_j [theta <= thetaMax_j(x)] / thetaMax_j(x), and
// the kernel's transitionRatio must be p_y(theta) / p_x(theta) (the solid-angle densities
// divide both by 2 pi sin theta). Checked in two parts: the angles drawn follow p_x (chi-square),
// and on every valid proposal the kernel's ratio is that formula with the scales c(x), c(y) it
// reports; c itself, the geometry, is checked by the single-component tests above (empirical
// detailed balance, CausticDetailedBalanceMatchesEmpiricalDensities).
TEST_F(ErptDensities, CausticRadiusMixtureDetailedBalance) {
    const std::optional<ChainPath> x = causticPath(recordPaths(4));
    ASSERT_TRUE(x) << "no caustic path recorded";
    const uint32_t n = 1 << 16;
    auto chain = chainBuffer(n);
    DensityPush push{};
    push.uniformLaw = 1;
    push.mixtureCount = 3;
    push.mixtureWeights = glm::vec3(0.5f, 0.3f, 0.2f);
    push.mixtureThetas = glm::vec3(0.01f, 0.03f, 0.09f);
    auto bound = [&](int j, double scale) {
        return std::min(double(push.mixtureThetas[j]) * scale, 0.5 * std::numbers::pi);
    };
    auto density = [&](double theta, double scale) {
        double p = 0.0;
        for (int j = 0; j < 3; ++j)
            if (theta <= bound(j, scale)) p += double(push.mixtureWeights[j]) / bound(j, scale);
        return p;
    };
    const auto first = propose(1, *x, n, 41, push, chain);
    const double scaleX = first[1].z;
    ASSERT_GT(scaleX, 0.0);
    // The angles drawn, in 48 cells over [0, largest bound], against the mixture's integral.
    const int cells = 48;
    const double top = bound(2, scaleX);
    std::vector<double> observed(cells, 0.0), expected(cells, 0.0);
    for (int c = 0; c < cells; ++c) {
        const double lo = top * c / cells, hi = top * (c + 1) / cells;
        for (int j = 0; j < 3; ++j)
            expected[size_t(c)] += double(n) * double(push.mixtureWeights[j]) *
                                   std::max(0.0, std::min(hi, bound(j, scaleX)) - lo) / bound(j, scaleX);
    }
    int valid = 0, differing = 0;
    double worst = 0.0;
    for (uint32_t i = 0; i < n; ++i) {
        const double theta = first[4 * i + 1].x;
        observed[size_t(std::min(cells - 1, int(theta / top * cells)))] += 1.0;
        if (first[4 * i].z < 0.5f) continue;
        ++valid;
        ASSERT_EQ(first[4 * i + 1].z, float(scaleX));
        const double scaleY = first[4 * i + 1].w;
        const double formula = density(theta, scaleY) / density(theta, scaleX);
        const double claimed = first[4 * i].w;
        worst = std::max(worst, std::abs(claimed / formula - 1.0));
        ASSERT_NEAR(claimed, formula, 1e-4 * formula) << "proposal " << i << ", theta " << theta;
        // Where x's and y's components covering theta differ, eq. 8 and eq. 9 part.
        if (std::abs(formula - scaleX / scaleY) > 1e-3 * formula) ++differing;
    }
    std::printf("  mixture theta: %s\n", chi2Test(observed, expected).describe().c_str());
    EXPECT_TRUE(chi2Passes(observed, expected, "caustic theta, radius mixture"));
    std::printf("  %d of %u mixture proposals valid, %d where eq. 8's ratio differs from eq. 9's; "
                "worst |kernel / formula - 1| %.2e\n",
                valid, n, differing, worst);
    EXPECT_GT(valid, int(n) / 10);
    EXPECT_GT(differing, 0);
}

// The caustic Gamma at a point light head (no |cos_g| there: its measure is a delta in
// position, path_space.glsl) against central differences: the head's position moved in the plane
// normal to its direction x_h -> x_h-1 and that direction turned, the specular chain retraced
// (erpt_density_test.comp mode 2), as JacobiansMatchFiniteDifferences does at area lights.
// Only paths E D L have a point light head: light sampling, the one way a path tracer reaches a
// delta light, starts at a non-specular vertex, so no seed path (and no path a mutation makes of
// one, the types being kept) is L S+ D E with L a point light.
TEST_F(ErptDensities, CausticGammaAtPointLightsMatchesFiniteDifferences) {
    useScene(cornellGlassWithPointLight());
    std::vector<ChainPath> paths;
    for (const ChainPath& p : recordPaths(4)) {
        if (p.head == 0 || !(p.vertices[p.head].flags & gpu::VERTEX_PUNCTUAL)) continue;
        EXPECT_EQ(p.head, 1u) << "a point light reached through a specular chain";
        if (paths.size() < 128) paths.push_back(p);
    }
    ASSERT_GE(paths.size(), 64u) << "the point light should light the walls";
    const uint32_t n = uint32_t(paths.size());
    std::vector<gpu::ChainVertex> packed(size_t(n) * 2 * kMaxVertices);
    std::vector<glm::uvec2> info(n);
    for (uint32_t j = 0; j < n; ++j) {
        std::copy(paths[j].vertices.begin(), paths[j].vertices.end(),
                  packed.begin() + size_t(j) * 2 * kMaxVertices);
        info[j] = {uint32_t(paths[j].vertices.size()), paths[j].head};
    }
    auto chain = storage(packed, "paths");
    const float extent = glm::length(m_scene->boundsMax - m_scene->boundsMin);
    DensityPush push{};
    push.mode = 2;
    push.count = n;
    std::vector<Jacobians> at[2];
    for (int s = 0; s < 2; ++s) {
        push.eps = extent * (s == 0 ? 2e-4f : 1e-4f);
        push.epsAngle = (s == 0 ? 2e-4f : 1e-4f);
        const auto r = call(push, size_t(64) * n, chain, {}, info);
        for (uint32_t j = 0; j < n; ++j) at[s].push_back(jacobians(r, size_t(64) * j, true));
    }
    int checked = 0;
    double worst = 0.0;
    for (uint32_t j = 0; j < n; ++j) {
        const Jacobians& a = at[0][j];
        const Jacobians& b = at[1][j];
        if (!(a.causticValid && b.causticValid && b.cosS12 > 0.05) ||
            std::abs(a.causticFd - b.causticFd) > 0.003 * std::max(a.causticFd, b.causticFd))
            continue;
        ++checked;
        const double ratio = b.causticGamma / b.cosS12 / b.causticFd;
        worst = std::max(worst, std::abs(ratio - 1.0));
        EXPECT_NEAR(ratio, 1.0, 0.025) << "causticGamma / |cos_s(x1 -> x2)| at a point light, path "
                                       << j << " (head " << paths[j].head << ")";
    }
    std::printf("  checked %d caustic Gamma at a point light (worst %.2e) of %u paths\n", checked,
                worst, n);
    EXPECT_GE(checked, int(n) / 2);
}

}  // namespace
}  // namespace pmcr::test
