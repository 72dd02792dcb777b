// Every scene in scenes/ loads, has a light, and renders a few samples of path tracing without a
// single NaN/Inf sample and without an all-black image; on one scene of each kernel variant, so do
// a few mutations per pixel of the Metropolis methods (mlt, pssmlt; mmlt on the box alone: their
// own path construction), a few photon passes (pm, pm-pmc: photons shot from every kind of light) and bidirectional
// samples (bdpt: light subpaths from every kind of light, splatted), without a dropped deposit.
// Third-party samples without a light of their own (glTF sample models) are lit by the shipped
// sky, as scenes/README.md says to.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "gpu_test.h"
#include "render_test.h"
#include "scene/gltf_loader.h"
#include "scene/scene.h"
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

// One scene of each kernel variant among the shipped scenes: the kernels are specialized for a
// scene's features (sceneFeatures: its material lobes, normal maps, alpha masks, textured
// emission) and built with or without the environment and punctual lights
// (lightsKernelVariant), so a method's kernels on two scenes of one variant are the same
// programs. Each is the first of its variant in sceneFiles()'s order, and
// SceneRenders.LoadsHasALightAndRendersWithoutNaNs (AllScenes) checks that every scene's variant
// is one of these. A method's suite renders all of them (lavapipe compiles each kernel of
// each variant once: 5-20 s each on CI's 2 cores).
const std::vector<std::string> kOneScenePerVariant = {
    "scenes/GlassVaseFlowers-sky.glb",   // normal maps, alpha masks, transmission; the sky
    "scenes/MetalRoughSpheres-sky.glb",  // glossy, opaque; the sky
    "scenes/checkers-two-lights.glb",    // glossy, opaque; area lights only
    "scenes/cornell-classic.glb",        // diffuse only
    "scenes/cornell-glass.glb",          // diffuse and glass
    "scenes/room.glb",                   // glossy and glass
    "scenes/sky-materials.glb",          // every lobe of issue 41; the sky
    "scenes/sky-spheres.glb",            // glossy and glass; the sky
};

// Every other scene of kOneScenePerVariant, from the first (parity 0) or the second (1).
std::vector<std::string> everyOtherVariant(size_t parity) {
    std::vector<std::string> files;
    for (size_t i = parity; i < kOneScenePerVariant.size(); i += 2) files.push_back(kOneScenePerVariant[i]);
    return files;
}

// The kernel variant a scene's renders use: its feature bits, and 1 << 31 when the kernels
// take the environment and punctual lights too.
uint64_t kernelVariant(const Scene& scene) {
    const bool otherLights = scene.environment.kind != gpu::ENV_NONE || !scene.punctualLights.empty();
    return uint64_t(sceneFeatures(scene)) | (uint64_t(otherLights) << 32);
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
    if (method == "pt") {  // AllScenes: every scene's kernels are among those the other suites build
        std::set<uint64_t> built;
        for (const std::string& f : kOneScenePerVariant) built.insert(kernelVariant(testScene(f)));
        EXPECT_TRUE(built.count(kernelVariant(scene)))
            << file << ": a kernel variant that kOneScenePerVariant lacks (features 0x" << std::hex
            << sceneFeatures(scene) << "): add this scene to it";
    }
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
    if (s.method == "mlt" || s.method == "pssmlt" || s.method == "mmlt")
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

// check: every scene with pt, and the other methods' own path construction (mlt, pssmlt, mmlt,
// bdpt) and photon shooting (pm, pm-pmc) on the box with a glass sphere. The full tier: every method on
// one scene of each kernel variant, pm and pm-pmc on every other one each (tests/CMakeLists.txt).
INSTANTIATE_TEST_SUITE_P(AllScenes, SceneRenders,
                         ::testing::Combine(::testing::ValuesIn(sceneFiles()), ::testing::Values("pt")),
                         paramName);
INSTANTIATE_TEST_SUITE_P(OneScene, SceneRenders,
                         ::testing::Combine(::testing::Values("scenes/cornell-glass.glb"),
                                            ::testing::Values("mlt", "pssmlt", "mmlt", "pm", "pm-pmc", "bdpt")),
                         paramName);
// One suite per method, so that ctest runs them as entries of their own, side by side and each
// well within its timeout. A second scene of a variant would render the same programs, so each
// suite takes one scene per variant: on every scene, mlt took 147 s and pm-pmc 217 s with a cold
// shader cache, mostly compiling; 70 s and 102 s on these (and with GALLIVM_PERF=nopt,
// tests/CMakeLists.txt). pm and pm-pmc shoot their photons with the same kernel and
// differ in the gather: each takes every other variant, so that every variant's photons are shot
// and both gathers see half of the variants.
INSTANTIATE_TEST_SUITE_P(EveryMethodMlt, SceneRenders,
                         ::testing::Combine(::testing::ValuesIn(kOneScenePerVariant), ::testing::Values("mlt")),
                         paramName);
// pssmlt over bdpt (its default) runs bdpt's own walks and strategies, which EveryMethodBdpt
// renders on every variant; over pt, the path tracer's. Each base takes every other variant, as
// pm and pm-pmc do.
INSTANTIATE_TEST_SUITE_P(EveryMethodPssmlt, SceneRenders,
                         ::testing::Combine(::testing::ValuesIn(everyOtherVariant(0)), ::testing::Values("pssmlt")),
                         paramName);
INSTANTIATE_TEST_SUITE_P(EveryMethodPssmltOverPt, SceneRenders,
                         ::testing::Combine(::testing::ValuesIn(everyOtherVariant(1)),
                                            ::testing::Values("pssmlt:over=pt")),
                         paramName);
INSTANTIATE_TEST_SUITE_P(EveryMethodPm, SceneRenders,
                         ::testing::Combine(::testing::ValuesIn(everyOtherVariant(0)), ::testing::Values("pm")),
                         paramName);
INSTANTIATE_TEST_SUITE_P(EveryMethodPmPmc, SceneRenders,
                         ::testing::Combine(::testing::ValuesIn(everyOtherVariant(1)), ::testing::Values("pm-pmc")),
                         paramName);
INSTANTIATE_TEST_SUITE_P(EveryMethodBdpt, SceneRenders,
                         ::testing::Combine(::testing::ValuesIn(kOneScenePerVariant), ::testing::Values("bdpt")),
                         paramName);

}  // namespace
}  // namespace pmcr::test
