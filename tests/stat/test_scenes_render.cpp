// Every scene in scenes/ loads, has a light, and renders a few samples of path tracing, and a
// few mutations per pixel of the Metropolis methods (mlt, pssmlt: their own path construction)
// and a few photon passes (pm, pm-pmc: photons shot from every kind of light) and bidirectional
// samples (bdpt: light subpaths from every kind of light, splatted),
// without a single NaN/Inf sample or dropped deposit and without an all-black image. Third-party samples without a light of
// their own (glTF sample models) are lit by the shipped sky, as scenes/README.md says to.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "gpu_test.h"
#include "render_test.h"
#include "scene/gltf_loader.h"
#include "test_util.h"

namespace pmcr::test {
namespace {

std::vector<std::string> sceneFiles() {
    std::vector<std::string> files;
    for (const auto& entry : std::filesystem::directory_iterator(sourcePath("scenes"))) {
        const auto ext = entry.path().extension();
        if (ext == ".glb" || ext == ".gltf") files.push_back("scenes/" + entry.path().filename().string());
    }
    std::sort(files.begin(), files.end());
    return files;
}

// Every other scene of sceneFiles(), from the first (parity 0) or the second (1).
std::vector<std::string> everyOtherScene(size_t parity) {
    std::vector<std::string> files;
    const auto all = sceneFiles();
    for (size_t i = parity; i < all.size(); i += 2) files.push_back(all[i]);
    return files;
}

class SceneRenders : public GpuTest,
                     public ::testing::WithParamInterface<std::tuple<std::string, std::string>> {};

const std::set<std::string> kLitBySky = {"scenes/MetalRoughSpheresNoTextures.glb"};

TEST_P(SceneRenders, LoadsHasALightAndRendersWithoutNaNs) {
    const auto& [file, method] = GetParam();
    Scene litBySky;
    if (kLitBySky.count(file))
        litBySky = loadScene(sourcePath(file), {sourcePath("scenes/sky-afternoon.exr").string()});
    const Scene& scene = kLitBySky.count(file) ? litBySky : testScene(file);
    EXPECT_TRUE(!buildEmitters(scene).emitters.empty() || !scene.punctualLights.empty() ||
                scene.environment.kind != gpu::ENV_NONE);
    EXPECT_FALSE(scene.cameras.empty());
    RenderSettings s;
    // "name" or "name:option=value".
    s.method = method.substr(0, method.find(':'));
    if (const size_t colon = method.find(':'); colon != std::string::npos) {
        const std::string option = method.substr(colon + 1);
        s.options[option.substr(0, option.find('='))] = option.substr(option.find('=') + 1);
    }
    s.spp = 2;
    s.width = 32;
    s.height = 24;
    auto r = renderForTest(scene, s);
    EXPECT_EQ(r.stats["nan_samples_dropped"].get<uint64_t>(), 0u);
    if (s.method == "mlt" || s.method == "pssmlt")
        EXPECT_EQ(r.stats["method_stats"]["deposits_dropped"].get<uint64_t>(), 0u);
    if (s.method == "pm" || s.method == "pm-pmc") {
        EXPECT_EQ(r.stats["method_stats"]["photon_paths_out_of_slots"].get<uint64_t>(), 0u);
        EXPECT_GT(r.stats["method_stats"]["photons_stored"].get<uint64_t>(), 0u);
    }
    double sum = 0.0;
    for (float v : r.output.image.rgb) {
        ASSERT_TRUE(std::isfinite(v));
        sum += v;
    }
    EXPECT_GT(sum, 0.0) << "an all-black image";
}

std::string paramName(const ::testing::TestParamInfo<std::tuple<std::string, std::string>>& info) {
    std::string name = std::filesystem::path(std::get<0>(info.param)).stem().string() + "_" +
                       std::get<1>(info.param);
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return name;
}

// check: every scene with pt, and the other methods' own path construction (mlt, pssmlt, bdpt)
// and photon shooting (pm, pm-pmc) on the box with a glass sphere. The full tier: every method on
// every scene, pm and pm-pmc on every other one each (tests/CMakeLists.txt).
INSTANTIATE_TEST_SUITE_P(AllScenes, SceneRenders,
                         ::testing::Combine(::testing::ValuesIn(sceneFiles()), ::testing::Values("pt")),
                         paramName);
INSTANTIATE_TEST_SUITE_P(OneScene, SceneRenders,
                         ::testing::Combine(::testing::Values("scenes/cornell-glass.glb"),
                                            ::testing::Values("mlt", "pssmlt", "pm", "pm-pmc", "bdpt")),
                         paramName);
// One suite per method, so that ctest runs them as entries of their own, side by side and each
// well within its timeout: a scene's kernels compile for its features (scene feature bits), so
// every scene costs every method a compilation. pm and pm-pmc shoot their photons with the same
// kernel and differ in the gather: each takes every other scene, so that every scene's photons
// are shot and both gathers see half of the scenes' features (the slowest entries of CI,
// 140 s and 178 s, now half as long).
INSTANTIATE_TEST_SUITE_P(EveryMethodMlt, SceneRenders,
                         ::testing::Combine(::testing::ValuesIn(sceneFiles()), ::testing::Values("mlt")), paramName);
// pssmlt over bdpt (its default) runs bdpt's own walks and strategies, which EveryMethodBdpt
// renders on every scene; over pt, the path tracer's. Each base takes every other scene, as pm
// and pm-pmc do (over bdpt on every scene took 106 s, 15 s before).
INSTANTIATE_TEST_SUITE_P(EveryMethodPssmlt, SceneRenders,
                         ::testing::Combine(::testing::ValuesIn(everyOtherScene(0)), ::testing::Values("pssmlt")),
                         paramName);
INSTANTIATE_TEST_SUITE_P(EveryMethodPssmltOverPt, SceneRenders,
                         ::testing::Combine(::testing::ValuesIn(everyOtherScene(1)),
                                            ::testing::Values("pssmlt:over=pt")),
                         paramName);
INSTANTIATE_TEST_SUITE_P(EveryMethodPm, SceneRenders,
                         ::testing::Combine(::testing::ValuesIn(everyOtherScene(0)), ::testing::Values("pm")),
                         paramName);
INSTANTIATE_TEST_SUITE_P(EveryMethodPmPmc, SceneRenders,
                         ::testing::Combine(::testing::ValuesIn(everyOtherScene(1)), ::testing::Values("pm-pmc")),
                         paramName);
INSTANTIATE_TEST_SUITE_P(EveryMethodBdpt, SceneRenders,
                         ::testing::Combine(::testing::ValuesIn(sceneFiles()), ::testing::Values("bdpt")), paramName);

}  // namespace
}  // namespace pmcr::test
