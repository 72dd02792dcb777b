#include "render_test.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include "gpu_test.h"
#include "scene/environment.h"
#include "scene/gltf_loader.h"
#include "scene_builder.h"
#include "test_util.h"

namespace pmcr::test {

const Scene& testScene(const std::string& relativePath) {
    static std::map<std::string, std::unique_ptr<Scene>> cache;
    auto& slot = cache[relativePath];
    if (!slot) slot = std::make_unique<Scene>(loadScene(sourcePath(relativePath)));
    return *slot;
}

Scene cornellGlassWithPointLights() { return withPointAndSpotLights("scenes/cornell-glass.glb"); }

Scene withPointAndSpotLights(const std::string& relativePath) {
    Scene s = testScene(relativePath);
    const glm::vec3 lo = s.boundsMin, hi = s.boundsMax, size = hi - lo;
    const float scale = glm::dot(size, size);
    s.punctualLights = {
        punctualLight(gpu::PUNCTUAL_POINT, lo + size * glm::vec3(0.25f, 0.8f, 0.6f), {0, -1, 0},
                      glm::vec3(0.6f, 0.5f, 0.4f) * scale * 0.05f),
        punctualLight(gpu::PUNCTUAL_SPOT, lo + size * glm::vec3(0.8f, 0.7f, 0.3f), {-0.5f, -1.0f, 0.3f},
                      glm::vec3(0.3f, 0.4f, 0.6f) * scale * 0.08f, 0.3f, 0.7f)};
    s.path = std::filesystem::path(relativePath).stem().string() + "-point-lights.glb";
    finalizeScene(s);
    return s;
}

Scene cornellGlassUnderSkyAndSun() {
    Scene s = testScene("scenes/cornell-glass.glb");
    const glm::vec3 forward = s.cameras[0].forward, up = s.cameras[0].up;
    s.environment = randomSkyImage(29, 0.0f, glm::vec3(2.0f));
    s.environment.image.set(7, 3, glm::vec3(8.0f, 7.0f, 6.0f));  // a sun (brighter ones make heavy tails)
    s.environment.rotation = 0.3f;
    s.punctualLights = {punctualLight(gpu::PUNCTUAL_DIRECTIONAL, {}, forward - 0.4f * up + 0.2f * s.cameras[0].right,
                                      {1.5f, 1.4f, 1.2f})};
    s.path = "cornell-glass-sky.glb";
    finalizeScene(s);
    return s;
}

RenderSettings renderSettings(const std::string& method, int width, int height, uint32_t spp,
                              uint32_t maxDepth) {
    RenderSettings s;
    s.method = method;
    s.width = width;
    s.height = height;
    s.spp = spp;
    s.maxDepth = maxDepth;
    return s;
}

RenderSettings chainZTestSettings(const std::string& method, uint32_t spp) {
    RenderSettings s = renderSettings(method, 20, 20, spp, 8);
    if (method == "erpt") {
        s.options["chain-length"] = "20";
        s.options["mutations-per-pixel"] = "4";
        s.options["mutation"] = "mix";
    } else if (method == "mlt") {
        s.options["mutation"] = "mix";
        s.options["bootstrap"] = "64";
    }
    return s;
}

void expectPssmltMutationsDepositOneUnit(RenderSettings settings, double energyTolerance) {
    settings.options["chains"] = "100";
    const RenderResult r = renderForTest(testScene("scenes/cornell-glass.glb"), settings);
    const auto& m = r.stats["method_stats"];
    EXPECT_EQ(m["passes"].get<int>(), 3);
    EXPECT_EQ(m["steps_per_pass"].get<uint32_t>(), 10u);  // round(1024 / 100)
    EXPECT_EQ(m["mutations"].get<uint64_t>(), 3000u);
    // --bootstrap samples per pixel (4 unless set), of each depth 0 .. maxDepth for mmlt.
    const auto option = settings.options.find("bootstrap");
    const uint64_t perPixel = option != settings.options.end() ? std::stoull(option->second) : 4u;
    const uint64_t depths = settings.method == "mmlt" ? settings.maxDepth + 1u : 1u;
    EXPECT_EQ(m["bootstrap_samples"].get<uint64_t>(), perPixel * 1024u * depths);
    EXPECT_EQ(m["deposits_dropped"].get<uint64_t>(), 0u);
    EXPECT_NEAR(m["energy_not_deposited"].get<double>(), 0.0, energyTolerance);
    const double large = m["large_step_proposed"].get<double>();
    const double small = m["small_step_proposed"].get<double>();
    EXPECT_EQ(large + small, 3000.0);
    EXPECT_NEAR(large / 3000.0, 0.3, 0.05);
    EXPECT_GT(m["large_step_acceptance"].get<double>(), 0.0);
    EXPECT_GT(m["small_step_acceptance"].get<double>(), m["large_step_acceptance"].get<double>());
    EXPECT_LT(m["small_step_acceptance"].get<double>(), 1.0);
    // b_hat is the image's total luminance: close to the rendered image's.
    const glm::dvec3 mean = imageMean(r.output.image);
    const double total = (0.2126 * mean.x + 0.7152 * mean.y + 0.0722 * mean.z) * 1024.0;
    EXPECT_NEAR(m["normalization"].get<double>() / total, 1.0, 0.5);
}

RenderResult renderForTest(const Scene& scene, RenderSettings settings) {
    settings.quiet = true;
    resolveImageSize(scene, settings);
    return renderScene(gpuContext(), scene, settings);
}

std::pair<RenderResult, RenderResult> expectPassesPerBatchKeepTheImage(const Scene& scene, RenderSettings settings,
                                                                       int together) {
    settings.options["passes-per-batch"] = "1";
    RenderResult one = renderForTest(scene, settings);
    settings.options["passes-per-batch"] = std::to_string(together);
    RenderResult batched = renderForTest(scene, settings);
    EXPECT_EQ(batched.stats["method_stats"]["passes_per_batch"].get<int>(), together);
    EXPECT_EQ(batched.stats["method_stats"]["passes"].get<uint32_t>(), settings.spp);
    EXPECT_EQ(one.output.image.rgb, batched.output.image.rgb) << settings.method;
    return {std::move(one), std::move(batched)};
}

glm::dvec3 imageMean(const Image& image) {
    glm::dvec3 sum(0.0);
    for (size_t i = 0; i < image.pixelCount(); ++i)
        sum += glm::dvec3(image.rgb[3 * i], image.rgb[3 * i + 1], image.rgb[3 * i + 2]);
    return sum / double(image.pixelCount());
}

ImageMoments renderMoments(const Scene& scene, RenderSettings settings, int renders, uint32_t firstSeed) {
    ImageMoments moments;
    for (int i = 0; i < renders; ++i) {
        settings.seed = firstSeed + uint32_t(i);
        moments.add(renderForTest(scene, settings).output.image.rgb);
    }
    return moments;
}

MeanEstimate meanOverRenders(const Scene& scene, RenderSettings settings, int renders, uint32_t firstSeed) {
    double sum = 0.0, sumSq = 0.0;
    for (int i = 0; i < renders; ++i) {
        settings.seed = firstSeed + uint32_t(i);
        const double m = imageMean(renderForTest(scene, settings).output.image).y;
        sum += m;
        sumSq += m * m;
    }
    MeanEstimate e;
    e.mean = sum / renders;
    e.standardError = std::sqrt(std::max(0.0, sumSq / renders - e.mean * e.mean) / (renders - 1));
    return e;
}

PixelTestResult zTestRenders(const Scene& scene, const RenderSettings& method, int renders,
                             uint32_t firstSeed, const ImageMoments& baseline) {
    const ImageMoments m = renderMoments(scene, method, renders, firstSeed);
    return pixelZTest(m.mean(), m.variance(), renders, baseline.mean(), baseline.variance(), baseline.count());
}

}  // namespace pmcr::test
