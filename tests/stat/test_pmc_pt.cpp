// PMC-PT: a seed gives the same image bit for bit; the furnace gives its analytic answer; the
// default estimator's mean image equals path tracing's pixel by pixel; the budget is
// the eye paths asked for; the diagnostics are there.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "gpu_test.h"
#include "render_test.h"
#include "statistics.h"

namespace pmcr::test {
namespace {

class PmcPtTest : public GpuTest {};

// Small images: a population of 24 members, one pool eye path per pixel per step, adapting
// after every other step, radii scaled to the image so that all three are used.
RenderSettings pmcPtSettings(int size, uint32_t spp) {
    RenderSettings s;
    s.method = "pmc-pt";
    s.width = size;
    s.height = size;
    s.spp = spp;
    s.maxDepth = 8;
    s.options["population"] = "24";
    s.options["mutations"] = "8";
    s.options["radii"] = "1.5,3,8";
    s.options["pool-spp"] = "1";
    s.options["adapt-every"] = "2";
    return s;
}

TEST_F(PmcPtTest, SameSeedSameImageBitForBit) {
    const Scene& scene = testScene("scenes/cornell-glass.glb");
    RenderSettings s = pmcPtSettings(32, 4);
    auto a = renderForTest(scene, s);
    auto b = renderForTest(scene, s);
    EXPECT_EQ(a.output.image.rgb, b.output.image.rgb);
    s.seed = 2;
    auto c = renderForTest(scene, s);
    EXPECT_NE(a.output.image.rgb, c.output.image.rgb);
}

TEST_F(PmcPtTest, TakesTheEyePathsAskedForAndWritesItsDiagnostics) {
    const Scene& scene = testScene("scenes/cornell-glass.glb");
    RenderSettings s = pmcPtSettings(32, 8);
    auto r = renderForTest(scene, s);
    const auto& m = r.stats["method_stats"];
    const uint64_t perUnit = m["eye_paths_per_unit"].get<uint64_t>();
    const uint64_t units = m["units"].get<uint64_t>();
    EXPECT_EQ(r.output.cameraSamples, perUnit * units);
    EXPECT_NEAR(r.output.samplesPerPixel, 8.0, 0.5 * double(perUnit) / (32.0 * 32.0));
    // The steps grow (1, 2, 2, 3, ... units at --step-growth 1.5), so fewer steps than units.
    EXPECT_LT(m["resample_steps"].get<uint64_t>(), units);
    ASSERT_EQ(r.output.diagnostics.size(), 2u);
    EXPECT_EQ(r.output.diagnostics[0].first, "strategy");
    EXPECT_EQ(r.output.diagnostics[1].first, "density");
    const Image& strategy = r.output.diagnostics[0].second;
    const Image& density = r.output.diagnostics[1].second;
    double paths = 0.0;
    for (size_t p = 0; p < density.pixelCount(); ++p) {
        paths += density.rgb[3 * p];
        const double share = strategy.rgb[3 * p] + strategy.rgb[3 * p + 1] + strategy.rgb[3 * p + 2];
        if (share > 0.0) EXPECT_NEAR(share, 1.0, 1e-5);
    }
    EXPECT_EQ(uint64_t(paths), r.output.cameraSamples);
    EXPECT_EQ(m["eliminated"].get<uint64_t>(),
              m["regenerated_from_pool"].get<uint64_t>() + m["regenerated_from_beta"].get<uint64_t>());
}

// Inside the furnace every pixel is 1 - 0.5^(D+1) (tests/stat/test_pt_furnace.cpp): the mean
// over pixels and renders, with its standard error from the renders' spread.
TEST_F(PmcPtTest, FurnaceGivesItsAnalyticValue) {
    const Scene& scene = testScene("scenes/furnace.glb");
    const int renders = 6, depth = 3;
    for (const char* estimator : {"steps", "average"}) {
        RenderSettings s = pmcPtSettings(24, 8);
        s.maxDepth = depth;
        s.options["estimator"] = estimator;
        const MeanEstimate e = meanOverRenders(scene, s, renders, 7);
        EXPECT_NEAR(e.mean, 1.0 - std::pow(0.5, depth + 1), 4.0 * e.standardError + 2e-3)
            << estimator << ": standard error " << e.standardError;
    }
}

// Independent path-traced renders of cornell-glass at the size of `like`.
ImageMoments pathTracedMoments(const RenderSettings& like, int renders, uint32_t spp) {
    RenderSettings pt = like;
    pt.method = "pt";
    pt.options.clear();
    pt.spp = spp;
    return renderMoments(testScene("scenes/cornell-glass.glb"), pt, renders, 5000);
}

// The mean of independent PMC-PT renders against independent path-traced renders, per pixel
// (Sidak-corrected z-test, at least 99.75% of pixels pass), on a small cornell-glass.
PixelTestResult zTestAgainstPathTracing(const RenderSettings& pmc, int pmcRenders, int ptRenders) {
    return zTestRenders(testScene("scenes/cornell-glass.glb"), pmc, pmcRenders, 1000,
                        pathTracedMoments(pmc, ptRenders, 64));
}

// Aggregate evidence of bias over all pixels (green channel): the sum of z^2 is chi-square with
// one degree of freedom per pixel if the method is unbiased; also the mean signed z.
struct BiasEvidence {
    PixelTestResult perPixel;
    double chi2 = 0.0;
    int dof = 0;
    double pValue = 1.0;
    double meanZ = 0.0;
    std::string describe() const {
        std::ostringstream s;
        s << "pixels passing " << perPixel.passFraction << ", sum z^2 " << chi2 << " over " << dof
          << " pixels (p " << pValue << "), mean z " << meanZ;
        return s.str();
    }
};

BiasEvidence measureBias(const RenderSettings& pmc, int pmcRenders, const ImageMoments& pt) {
    const ImageMoments e = renderMoments(testScene("scenes/cornell-glass.glb"), pmc, pmcRenders, 1000);
    BiasEvidence b;
    const auto m = e.mean(), v = e.variance(), r = pt.mean(), rv = pt.variance();
    b.perPixel = pixelZTest(m, v, pmcRenders, r, rv, pt.count());
    double sumZ = 0.0;
    for (size_t i = 1; i < m.size(); i += 3) {
        const double var = v[i] / pmcRenders + rv[i] / pt.count();
        if (var <= 0.0) continue;
        const double z = (double(m[i]) - double(r[i])) / std::sqrt(var);
        b.chi2 += z * z;
        sumZ += z;
        ++b.dof;
    }
    b.meanZ = b.dof > 0 ? sumZ / b.dof : 0.0;
    b.pValue = chi2Survival(b.chi2, b.dof);
    return b;
}

// Measures the bias of the paper's plain average next to the weighted estimator (run with
// --gtest_also_run_disabled_tests; the numbers are quoted in methods/pmc_pt/pmc_pt_integrator.h).
TEST_F(PmcPtTest, DISABLED_MeasurePlainAverageBias) {
    const int renders = 100;
    RenderSettings s = pmcPtSettings(24, 16);
    s.options.erase("population");
    s.options["defensive"] = "0.1";  // the adaptive part at its strongest
    const ImageMoments pt = pathTracedMoments(s, 32, 256);
    // Control: path tracing itself at the same budget (a heavy-tailed pixel's z is skewed).
    RenderSettings control = s;
    control.method = "pt";
    control.options.clear();
    std::printf("pt: %s\n", measureBias(control, renders, pt).describe().c_str());
    for (const char* estimator : {"steps", "average"}) {
        s.options["estimator"] = estimator;
        std::printf("%s: %s\n", estimator, measureBias(s, renders, pt).describe().c_str());
    }
}

TEST_F(PmcPtTest, UnbiasedAgainstPathTracing) {
    const auto result = zTestAgainstPathTracing(pmcPtSettings(24, 16), 40, 16);
    EXPECT_GE(result.passFraction, 0.9975) << result.describe();
}

// A tenth of the eye paths defensive (a population of 648): the density follows the population
// most closely.
TEST_F(PmcPtTest, UnbiasedAgainstPathTracingWithLittleDefensiveSampling) {
    RenderSettings s = pmcPtSettings(24, 16);
    s.options.erase("population");
    s.options["defensive"] = "0.1";
    const auto result = zTestAgainstPathTracing(s, 40, 16);
    EXPECT_GE(result.passFraction, 0.9975) << result.describe();
}

}  // namespace
}  // namespace pmcr::test
