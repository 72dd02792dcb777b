// Every scene in scenes/ loads, has a light, and renders a few samples of path tracing without
// a single NaN/Inf sample and without an all-black image.
#include <gtest/gtest.h>

#include <filesystem>

#include "gpu_test.h"
#include "render_test.h"
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

class SceneRenders : public GpuTest, public ::testing::WithParamInterface<std::string> {};

TEST_P(SceneRenders, LoadsHasALightAndRendersWithoutNaNs) {
    const Scene& scene = testScene(GetParam());
    EXPECT_FALSE(buildEmitters(scene).emitters.empty());
    EXPECT_FALSE(scene.cameras.empty());
    RenderSettings s;
    s.method = "pt";
    s.spp = 2;
    s.width = 32;
    s.height = 24;
    auto r = renderForTest(scene, s);
    EXPECT_EQ(r.stats["nan_samples_dropped"].get<uint64_t>(), 0u);
    double sum = 0.0;
    for (float v : r.output.image.rgb) {
        ASSERT_TRUE(std::isfinite(v));
        sum += v;
    }
    EXPECT_GT(sum, 0.0) << "an all-black image";
}

INSTANTIATE_TEST_SUITE_P(AllScenes, SceneRenders, ::testing::ValuesIn(sceneFiles()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                             std::string name = std::filesystem::path(info.param).stem().string();
                             for (char& c : name)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return name;
                         });

}  // namespace
}  // namespace pmcr::test
