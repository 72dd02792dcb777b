// The papers' baselines as options (render/baseline_options.h): independent pixel samples and
// the balance heuristic estimate the same images as pmcr's defaults (per-pixel z-tests of
// independent renders), every method that offers an option takes it (its image changes) and
// stays deterministic with it.
#include <gtest/gtest.h>

#include <string>

#include "gpu_test.h"
#include "render/methods.h"
#include "render_test.h"
#include "statistics.h"

namespace pmcr::test {
namespace {

class PaperBaselines : public GpuTest {};

RenderSettings smallRender(const std::string& method, int size, uint32_t spp) {
    return renderSettings(method, size, size, spp, 6);
}

// The mean of `renders` renders with `option` = `value` against as many with the default, per
// pixel (Sidak-corrected z-test; at least 99.75% of pixels pass, as Mitsuba's render tests).
void expectSameEstimate(const std::string& sceneName, RenderSettings s, const std::string& option,
                        const std::string& value, int renders) {
    const Scene& scene = testScene(sceneName);
    const ImageMoments defaults = renderMoments(scene, s, renders, 1000);
    s.options[option] = value;
    const auto result = zTestRenders(scene, s, renders, 2000, defaults);
    EXPECT_GE(result.passFraction, 0.9975) << s.method << " --" << option << " " << value << ": "
                                           << result.describe();
}

// The PMC-IP and PMC-PT papers' uniform image-plane sampling: positions uniform in the pixel
// without stratification, so only the variance changes.
TEST_F(PaperBaselines, IndependentPixelSamplesEstimateTheSameImage) {
    expectSameEstimate("scenes/cornell-spheres.glb", smallRender("pt", 24, 8), "pixel-sampler",
                       "independent", 16);
}

// The balance heuristic weighs the same light and BSDF samples differently; the weights of
// each pair still sum to one (tests/gpu/test_sampling.cpp), so the estimate is unchanged.
TEST_F(PaperBaselines, BalanceHeuristicEstimatesTheSameImage) {
    expectSameEstimate("scenes/cornell-spheres.glb", smallRender("pt", 24, 8), "mis", "balance",
                       16);
    // direct's multi-sample MIS (n light and n BSDF samples, Veach 1997 sec. 9.2.4), on
    // glossy surfaces lit by lights of two sizes, where the two heuristics differ most.
    RenderSettings direct = smallRender("direct", 24, 4);
    direct.options["light-samples"] = "2";
    expectSameEstimate("scenes/checkers-two-lights.glb", direct, "mis", "balance", 16);
}

// Every method that lists an option takes it: its image differs from the default's, and a seed
// still gives the same image bit for bit.
TEST_F(PaperBaselines, EveryMethodThatOffersAnOptionTakesIt) {
    const Scene& scene = testScene("scenes/cornell-spheres.glb");
    const std::pair<const char*, const char*> choices[] = {{"pixel-sampler", "independent"},
                                                           {"mis", "balance"}};
    int checked = 0;
    for (const MethodInfo& m : methods()) {
        for (const auto& [option, value] : choices) {
            bool offered = false;
            for (const MethodOption& o : m.options) offered = offered || o.name == option;
            if (!offered) continue;
            SCOPED_TRACE(m.name + " --" + option + " " + value);
            RenderSettings s = smallRender(m.name, 16, 8);
            if (m.name == "pmc-pt") {  // a population the size of this image (test_pmc_pt.cpp)
                s.options["population"] = "24";
                s.options["mutations"] = "8";
                s.options["radii"] = "1.5,3,8";
            }
            const auto defaults = renderForTest(scene, s).output.image.rgb;
            s.options[option] = value;
            const auto a = renderForTest(scene, s).output.image.rgb;
            const auto b = renderForTest(scene, s).output.image.rgb;
            EXPECT_NE(a, defaults);
            EXPECT_EQ(a, b);
            ++checked;
        }
    }
    // pt, direct, bdpt, pmc-ip, pmc-ip-direct, pmc-pt take both; pmc-hi, pmc-ip-hi and pm-pmc
    // (PMC-IP over photon mapping's gather) the sampler.
    EXPECT_EQ(checked, 15);
}

}  // namespace
}  // namespace pmcr::test
