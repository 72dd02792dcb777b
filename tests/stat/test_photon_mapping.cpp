// Photon mapping (pm, pm-pmc; host/methods/pm/): the photons of a pass carry the lights' power,
// the density estimate of a furnace gives its analytic answer, the progressive radius makes the
// image converge to path tracing's, and pm-pmc's adaptive gather (PMC-IP over the image plane,
// PMC-HI for direct light) estimates what pm's plain gather does from the same photon map.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "core/random.h"
#include "gpu_test.h"
#include "methods/pm/photon_map.h"
#include "methods/pt/pt_integrator.h"
#include "metrics/metrics.h"
#include "render/session.h"
#include "render_test.h"
#include "statistics.h"

namespace pmcr::test {
namespace {

class PhotonMapping : public GpuTest {};

// The furnaces' answer with at most D bounces (tests/stat/test_pt_furnace.cpp).
double furnaceAnswer(int maxDepth) { return 1.0 - std::pow(0.5, maxDepth + 1); }

// Mean of the green channel over the pixels of `image` and its standard error.
MeanEstimate pixelMean(const Image& image) {
    double sum = 0.0, sumSq = 0.0;
    const size_t n = image.pixelCount();
    for (size_t i = 0; i < n; ++i) {
        const double y = image.rgb[3 * i + 1];
        sum += y;
        sumSq += y * y;
    }
    MeanEstimate m;
    m.mean = sum / double(n);
    m.standardError = std::sqrt(std::max(0.0, sumSq / double(n) - m.mean * m.mean) / double(n));
    return m;
}

TEST_F(PhotonMapping, SameSeedSameImageBitForBit) {
    for (const char* method : {"pm", "pm-pmc"}) {
        RenderSettings s = renderSettings(method, 24, 24, 8);
        const Scene& scene = testScene("scenes/cornell-glass.glb");
        auto a = renderForTest(scene, s);
        auto b = renderForTest(scene, s);
        EXPECT_EQ(a.output.image.rgb, b.output.image.rgb) << method;
    }
}

// The grid's sort, spread over the cores in blocks, is one thread's stable counting sort: every
// bucket holds its photons in path order (what makes a seed's map the same bit for bit), for a
// hash table of few buckets (many photons each, across blocks) and of many.
TEST(PhotonGrid, SortIsAStableCountingSortByBucket) {
    Pcg32 rng(7, 0);
    std::vector<gpu::Photon> photons(100000);
    for (size_t i = 0; i < photons.size(); ++i) {
        photons[i] = gpu::Photon{};
        photons[i].position = glm::vec3(float(rng.nextDouble()), float(rng.nextDouble()), float(rng.nextDouble())) * 4.0f - 2.0f;
        photons[i].flags = uint32_t(i);  // the path order
    }
    for (uint32_t hashSize : {1024u, 1u << 18}) {
        std::vector<gpu::Photon> sorted;
        std::vector<glm::uvec2> cells;
        buildPhotonGrid(photons, 0.05f, hashSize, sorted, cells);
        // One thread's counting sort.
        std::vector<std::vector<uint32_t>> buckets(hashSize);
        for (const gpu::Photon& p : photons) {
            const glm::vec3 c = glm::floor(p.position / 0.05f);
            buckets[photonCellBucket(int32_t(c.x), int32_t(c.y), int32_t(c.z), hashSize)].push_back(p.flags);
        }
        ASSERT_EQ(cells.size(), size_t(hashSize));
        ASSERT_EQ(sorted.size(), photons.size());
        uint32_t first = 0;
        for (uint32_t b = 0; b < hashSize; ++b) {
            ASSERT_EQ(cells[b], glm::uvec2(first, uint32_t(buckets[b].size()))) << "bucket " << b;
            for (uint32_t k = 0; k < cells[b].y; ++k) ASSERT_EQ(sorted[first + k].flags, buckets[b][k]);
            first += cells[b].y;
        }
    }
}

// In a closed furnace every photon path's first hit stores a direct photon, and each carries
// Phi / N exactly (emission in proportion to power, uniform emitters): one pass's direct photons
// sum to the emitted power. Their count, and the caustic flag (no delta surfaces), are checked too.
TEST_F(PhotonMapping, OnePassCarriesTheEmittedPower) {
    const Scene& scene = testScene("scenes/furnace.glb");
    RenderSettings settings = renderSettings("pm", 16, 16, 1);
    RenderSession session(context(), scene, settings, 16, 16);
    PhotonMapOptions options;
    options.photonsPerPass = 20000;
    PhotonMap map(session, options, 1.0);
    vk::DescriptorSet work(session.layout(), vk::DescriptorSet::Kind::Work, "photon test");
    bindTileWork(work, session.film(), session);
    map.preparePass(0, work);
    glm::dvec3 direct(0.0);
    uint32_t directCount = 0, caustic = 0;
    for (const gpu::Photon& p : map.photons()) {
        ASSERT_TRUE(std::isfinite(p.power.x) && std::isfinite(p.power.y) && std::isfinite(p.power.z));
        if (p.flags & gpu::PHOTON_DIRECT) {
            direct += glm::dvec3(p.power);
            ++directCount;
        }
        if (p.flags & gpu::PHOTON_CAUSTIC) ++caustic;
    }
    EXPECT_EQ(directCount, options.photonsPerPass);
    EXPECT_EQ(caustic, 0u);
    // Grey emitters: every channel's power is the luminance power the light tables hold.
    const double power = session.scene().info().totalEmitterPower;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(direct[c], power, 1e-3 * power) << "channel " << c;
    // Hit h carries 0.5^(h-1) of it (albedo 0.5) in expectation, roulette included: all D hits
    // sum to 2 (1 - 0.5^D) times the power.
    glm::dvec3 all(0.0);
    for (const gpu::Photon& p : map.photons()) all += glm::dvec3(p.power);
    EXPECT_NEAR(all.y / power, 2.0 * furnaceAnswer(int(settings.maxDepth) - 1), 0.03);
}

// The furnace's density estimate (every surface Lambertian, albedo 0.5, emitting 0.5): emission
// seen, MIS direct light, and the final gather's photon lookups sum to L = 1 - 0.5^(D+1).
// On the sphere a disc of radius r around a point holds exactly pi r^2 of surface, so the
// estimate's bias comes from the tessellation and the depth limit alone; the tolerance shrinks
// with the radius (fixed radius, --progressive off) and holds for every kernel, for reading
// the map at the gather point (--gather-rays 0) and for direct light at the gather rays' hits by
// light sampling (--gather-direct on: the photons there stand for indirect light only). At
// small depths the answer tells whether photons end paths beyond --max-depth (each photon's hit
// index limits the lookups that may read it).
TEST_F(PhotonMapping, FurnaceDensityEstimateGivesTheAnalyticAnswer) {
    const Scene& scene = testScene("scenes/furnace.glb");
    struct Case {
        double radius;
        const char* kernel;
        const char* gatherRays;
        const char* gatherDirect;
        int maxDepth;
    };
    for (const Case& c :
         {Case{0.4, "epanechnikov", "4", "off", 16}, Case{0.1, "epanechnikov", "4", "off", 16},
          Case{0.1, "cone", "4", "off", 16}, Case{0.1, "box", "0", "off", 16},
          Case{0.4, "epanechnikov", "4", "on", 16}, Case{0.1, "epanechnikov", "4", "off", 2},
          Case{0.1, "box", "0", "off", 2}, Case{0.1, "epanechnikov", "4", "on", 3}}) {
        RenderSettings s = renderSettings("pm", 32, 32, 16, uint32_t(c.maxDepth));
        s.options["progressive"] = "off";
        s.options["radius"] = std::to_string(c.radius);
        s.options["kernel"] = c.kernel;
        s.options["gather-rays"] = c.gatherRays;
        s.options["gather-direct"] = c.gatherDirect;
        s.options["photons"] = "40000";
        auto r = renderForTest(scene, s);
        const MeanEstimate m = pixelMean(r.output.image);
        // One photon map: its own noise (photons per disc) is shared by all pixels, so allow
        // 2% on top of the pixels' 5 sigma, plus a bias term proportional to r.
        const double tolerance = 5.0 * m.standardError + 0.02 + 0.05 * c.radius;
        EXPECT_NEAR(m.mean, furnaceAnswer(c.maxDepth), tolerance)
            << "radius " << c.radius << " kernel " << c.kernel << " gather rays " << c.gatherRays
            << " gather direct " << c.gatherDirect << " max depth " << c.maxDepth;
    }
}

// The green channel's sums over the 2 x 2 quadrants of `image` (even width and height).
std::array<double, 4> quadrantSums(const Image& image) {
    const int w = image.width, h = image.height;
    std::array<double, 4> sums{};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            sums[(2 * y / h) * 2 + 2 * x / w] += image.rgb[3 * (size_t(y) * w + size_t(x)) + 1];
    return sums;
}

// Progressive photon mapping converges to the path tracer's image: its Err against a pt
// reference falls from pass count to pass count, and at the end the image's quadrants have
// pt's means within 2% (the reference's own noise included: at 1024 spp the glass sphere's
// quadrant of the reference was 1.5% bright, so it takes 4096).
TEST_F(PhotonMapping, ProgressiveConvergesToPathTracing) {
    const Scene& scene = testScene("scenes/cornell-glass.glb");
    RenderSettings ref = renderSettings("pt", 48, 48, 4096, 8);
    const Image reference = renderForTest(scene, ref).output.image;
    RenderSettings s = renderSettings("pm", 48, 48, 64, 8);
    s.snapshotSpp = {4, 16};
    auto r = renderForTest(scene, s);
    ASSERT_EQ(r.snapshots.size(), 2u);
    std::vector<double> errs;
    for (const Snapshot& snap : r.snapshots) errs.push_back(measureError(snap.image, reference).mse);
    errs.push_back(measureError(r.output.image, reference).mse);
    EXPECT_LT(errs[1], errs[0]) << errs[0] << " " << errs[1];
    EXPECT_LT(errs[2], errs[1]) << errs[1] << " " << errs[2];
    const std::array<double, 4> a = quadrantSums(r.output.image), b = quadrantSums(reference);
    for (int q = 0; q < 4; ++q) EXPECT_NEAR(a[q] / b[q], 1.0, 0.02) << "quadrant " << q;
}

// Issue 24's "block means within 1%", on a scene whose pt reference is cheap to make precise:
// the diffuse Cornell box (no caustics, so the reference's quadrant means are within 0.1% at
// 4096 spp), where 64 spp of progressive pm end within 1% in every quadrant (measured: 0.59%
// at most; 0.24% at 256 spp). bench/photon checks lamp-room and room, with references of an
// hour's rendering.
TEST_F(PhotonMapping, ProgressiveQuadrantsWithinOnePercentOnTheDiffuseBox) {
    const Scene& scene = testScene("scenes/cornell-classic.glb");
    RenderSettings ref = renderSettings("pt", 48, 48, 4096, 8);
    RenderSettings s = renderSettings("pm", 48, 48, 64, 8);
    const std::array<double, 4> a = quadrantSums(renderForTest(scene, s).output.image);
    const std::array<double, 4> b = quadrantSums(renderForTest(scene, ref).output.image);
    for (int q = 0; q < 4; ++q) EXPECT_NEAR(a[q] / b[q], 1.0, 0.01) << "quadrant " << q;
}

// pm-pmc against pm with the same photon map (one map at a fixed radius, a fixed photon seed):
// given the map, both gathers estimate the same image, pm-pmc's with PMC-IP's unbiased image
// estimator (sec. 4) and PMC-HI's unbiased direct lighting (sec. 5), so their means over
// independent camera seeds pass the per-pixel z-test.
TEST_F(PhotonMapping, PmcGatherEstimatesThePlainGather) {
    const Scene& scene = testScene("scenes/cornell-glass.glb");
    RenderSettings base = renderSettings("pm", 20, 20, 16, 6);
    base.options["progressive"] = "off";
    base.options["photon-seed"] = "11";
    base.options["radius"] = "0.1";
    base.options["photons"] = "20000";
    RenderSettings pmc = base;
    pmc.method = "pm-pmc";
    const auto result = zTestRenders(scene, pmc, 16, 3000, renderMoments(scene, base, 16, 9000));
    EXPECT_GE(result.passFraction, 0.9975) << result.describe();
}

}  // namespace
}  // namespace pmcr::test
