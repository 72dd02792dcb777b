// The densities in ERPT's Metropolis-Hastings acceptance (shaders/common/path_space.glsl,
// mutate_lens.glsl, mutate_caustic.glsl), against numerical estimates, on paths the pt_record
// kernel records in cornell-glass:
//  - the Jacobians the target function F_nu = lum(P) Gamma carries: rasterDensity = |du/dA(x1)|,
//    reconnectionFactor / |cos_s| = |dw/dA(x2)| and the caustic Gamma / |cos_s(x1 -> x2)| =
//    |d(u, w_1) / d(A_h, w_h)| (etendue through the specular chain), each against central
//    differences of the renderer's own camera projection and specular retracing;
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "gpu_test.h"
#include "render/session.h"
#include "render_test.h"
#include "vk/command_batch.h"

namespace pmcr::test {
namespace {

constexpr uint32_t kMaxVertices = gpu::CHAIN_MAX_VERTICES;
constexpr int kSize = 32;  // image side of the recorded paths

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
            return i;
    return 0;
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
        GpuTest::TearDown();
    }

    // Light paths of `passes` path-traced samples per pixel, split as erpt_seed.comp splits
    // them (every implicit and explicit path of a record with a non-zero contribution).
    std::vector<ChainPath> recordPaths(uint32_t passes) {
        const uint32_t pixels = kSize * kSize;
        vk::Kernel ptRecord(m_session->layout(), "pt_record");
        Film& film = m_session->film();
        vk::Buffer records(context(), pixels * sizeof(gpu::PathRecord),
                           VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "path records");
        vk::Buffer vertices(context(), pixels * gpu::PATH_MAX_VERTICES * sizeof(gpu::PathVertex),
                            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "path vertices");
        vk::DescriptorSet work(m_session->layout(), vk::DescriptorSet::Kind::Work, "record work");
        work.bind(gpu::PT_BINDING_FILM, film.pixels());
        work.bind(gpu::PT_BINDING_COUNTERS, film.counters());
        work.bind(gpu::PT_BINDING_REQUESTS, m_session->placeholder());
        work.bind(gpu::PT_BINDING_RESULTS, m_session->placeholder());
        work.bind(gpu::PT_BINDING_PATH_RECORDS, records);
        work.bind(gpu::PT_BINDING_PATH_VERTICES, vertices);
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
            const auto recs = records.download<gpu::PathRecord>(pixels);
            const auto verts = vertices.download<gpu::PathVertex>(pixels * gpu::PATH_MAX_VERTICES);
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
                                flags = gpu::VERTEX_EMITTER;
                            }
                            p.vertices.push_back(
                                {pv.triangle, pv.barycentrics.x, pv.barycentrics.y, flags});
                        }
                        if (kind == 1)
                            p.vertices.push_back(
                                {end.lightTriangle, end.lightB1, end.lightB2, gpu::VERTEX_EMITTER});
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

    vk::Buffer chainBuffer(uint32_t chains) {
        return zeros(size_t(chains) * 2 * kMaxVertices * sizeof(gpu::ChainVertex),
                     "chain vertices");
    }

    std::unique_ptr<RenderSession> m_session;
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
TEST_F(ErptDensities, JacobiansMatchFiniteDifferences) {
    std::vector<ChainPath> all = recordPaths(4);
    std::vector<ChainPath> paths;
    int withChain = 0;
    for (const ChainPath& p : all) {
        if (p.vertices[0].flags & gpu::VERTEX_SPECULAR)
            continue;
        // Half of them through a specular chain (h > 1) where the scene has them.
        if (p.head > 1 && withChain < 128) {
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
    const Scene& scene = testScene("scenes/cornell-glass.glb");
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
        // percent: only paths whose two estimates agree within 0.3% are compared.
        if (a.causticValid && b.causticValid && b.cosS12 > 0.05 &&
            agree(a.causticFd, b.causticFd, 0.003)) {
            ++causticChecked;
            if (paths[j].head > 1)
                ++causticChainChecked;
            const double ratio = b.causticGamma / b.cosS12 / b.causticFd;
            worstCaustic = std::max(worstCaustic, std::abs(ratio - 1.0));
            EXPECT_NEAR(ratio, 1.0, 0.025)
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

}  // namespace
}  // namespace pmcr::test
