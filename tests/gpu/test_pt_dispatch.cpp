// The per-camera-sample kernels with PT_SOURCE_TILE (shaders/methods/pt/camera_sample_kernel.glsl):
// several passes in one dispatch (samplesPerPixel > 1, as pt does on small images) must leave
// the film exactly as one dispatch per pass does, so an image does not depend on how the
// dispatch sizer, which follows the clock, split the passes; and pt.comp's paths in turn
// (PtPush::itemsPerInvocation) must leave film and results as one path per invocation does.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

#include "gpu_test.h"
#include "methods/pt/pt_integrator.h"
#include "render/session.h"
#include "render_test.h"
#include "scene/scene.h"
#include "vk/command_batch.h"

namespace pmcr::test {
namespace {

// One tile-mode kernel on cornell-spheres at width x height: the session and its work set.
struct TileRig {
    TileRig(vk::Context& context, int width, int height, const char* kernelName,
            uint32_t sceneFeatures = 0, const char* scene = "scenes/cornell-spheres.glb")
        : session(context, testScene(scene), settingsOf(width, height), width, height),
          kernel(session.layout(), kernelName, sceneFeatures),
          work(session.layout(), vk::DescriptorSet::Kind::Work, "dispatch test work") {
        bindTileWork(work, session.film(), session);
    }
    static RenderSettings settingsOf(int width, int height) {
        RenderSettings settings;
        settings.width = width;
        settings.height = height;
        return settings;
    }
    // Runs `dispatches` (each a push and its invocation count) in one batch on a cleared film.
    void run(const std::vector<std::pair<gpu::PtPush, uint32_t>>& dispatches) {
        session.film().clear();
        vk::CommandBatch batch(session.layout());
        batch.bind(session.scene().descriptorSet());
        batch.bind(work);
        for (const auto& [push, invocations] : dispatches) batch.dispatch(kernel, push, invocations);
        batch.submitAndWait();
    }
    RenderSession session;
    vk::Kernel kernel;
    vk::DescriptorSet work;
};

gpu::PtPush tilePush(uint32_t seed) {
    gpu::PtPush push{};
    push.source = gpu::PT_SOURCE_TILE;
    push.flags = gpu::PT_FLAG_DEPOSIT;
    push.seed = seed;
    push.maxDepth = 8;
    push.rrDepth = 3;
    push.lightSamples = 2;
    return push;
}

uint32_t invocationsFor(uint32_t items, uint32_t perInvocation) {
    const uint32_t p = std::max(perInvocation, 1u);
    return (items + p - 1) / p;
}

// Films equal bit for bit, each pixel with `samples` samples, and not black.
void expectSameFilm(const std::vector<gpu::FilmPixel>& a, const std::vector<gpu::FilmPixel>& b,
                    uint32_t samples, const std::string& what) {
    ASSERT_EQ(a.size(), b.size());
    double total = 0.0;
    for (size_t i = 0; i < a.size(); ++i) {
        ASSERT_EQ(a[i].sampleCount, samples) << "pixel " << i;
        ASSERT_EQ(std::memcmp(&a[i], &b[i], sizeof(gpu::FilmPixel)), 0) << "pixel " << i << ", " << what;
        total += a[i].sum.x;
    }
    EXPECT_GT(total, 0.0);
}

class PtDispatch : public GpuTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(PtDispatch, SeveralPassesInOneDispatchGiveTheSameFilm) {
    TileRig rig(context(), 24, 24, GetParam());
    const uint32_t pixels = 24 * 24;
    const uint32_t passes = 5;
    // Passes 3 .. 3 + passes - 1 in `perDispatch` passes per dispatch.
    auto render = [&](uint32_t perDispatch) {
        std::vector<std::pair<gpu::PtPush, uint32_t>> dispatches;
        for (uint32_t pass = 0; pass < passes; pass += perDispatch) {
            gpu::PtPush push = tilePush(7);
            push.invocationCount = pixels;
            push.sampleBase = 3 + pass;
            push.samplesPerPixel = std::min(perDispatch, passes - pass);
            dispatches.push_back({push, pixels});
        }
        rig.run(dispatches);
        return rig.session.film().download();
    };
    const auto onePerDispatch = render(1);
    expectSameFilm(onePerDispatch, render(passes), passes, "all passes in one dispatch");
    expectSameFilm(onePerDispatch, render(2), passes, "two passes per dispatch");
}

INSTANTIATE_TEST_SUITE_P(Kernels, PtDispatch,
                         ::testing::Values("methods/pt/pt", "methods/pt/direct"));

// pt.comp's paths in turn: however many pixels each invocation takes, every pixel gets the
// same samples in the same order from one writer, so the film is the same bit for bit; a tile
// whose pixel count is not a multiple of P, and a tile that does not start at pixel 0, included.
TEST_F(GpuTest, PtPixelsPerInvocationLeavesTheFilmUnchanged) {
    TileRig rig(context(), 23, 19, "methods/pt/pt");
    const uint32_t pixels = 23 * 19;
    // The image in two tiles (pixels [0, 100) and [100, pixels)), 3 passes, P pixels each.
    auto render = [&](uint32_t P) {
        std::vector<std::pair<gpu::PtPush, uint32_t>> dispatches;
        for (auto [offset, count] : {std::pair<uint32_t, uint32_t>{0, 100}, {100, pixels - 100}}) {
            gpu::PtPush push = tilePush(11);
            push.sampleBase = 2;
            push.samplesPerPixel = 3;
            push.itemsPerInvocation = P;
            push.pixelOffset = offset;
            push.invocationCount = count;
            dispatches.push_back({push, invocationsFor(count, P)});
        }
        rig.run(dispatches);
        return rig.session.film().download();
    };
    const auto reference = render(1);
    for (uint32_t P : {0u, 3u, 8u, 64u}) expectSameFilm(reference, render(P), 3, "P = " + std::to_string(P));
}

// A scene without GGX lobes (cornell-spheres: Lambertian walls, a mirror and a glass sphere)
// renders the same with the microfacet code compiled out (SCENE_FEATURE_NO_GLOSSY, which the
// host sets for it) as with it compiled in, and one without glass (veach-mis: rough metal
// plates) the same without the glass lobe (SCENE_FEATURE_NO_TRANSMISSION), and cornell-glass
// the same without issue 41's material features (BLEND, thin sheets, specular, clear coat,
// sheen): bit for bit on lavapipe, within float rounding where a compiler fuses the variants'
// multiply-adds differently.
class PtLacks : public GpuTest,
                public ::testing::WithParamInterface<std::pair<const char*, uint32_t>> {};

TEST_P(PtLacks, CompilingOutWhatTheSceneLacksLeavesTheFilmUnchanged) {
    const auto [scene, lack] = GetParam();
    ASSERT_EQ(sceneFeatures(testScene(scene)) & lack, lack);
    auto render = [&, scene = scene](uint32_t features) {
        TileRig rig(context(), 24, 24, "methods/pt/pt", features, scene);
        gpu::PtPush push = tilePush(5);
        push.invocationCount = 24 * 24;
        push.samplesPerPixel = 4;
        rig.run({{push, push.invocationCount}});
        return rig.session.film().download();
    };
    const auto with = render(0);
    const auto without = render(lack);
    ASSERT_EQ(with.size(), without.size());
    double total = 0.0;
    for (size_t i = 0; i < without.size(); ++i) {
        ASSERT_EQ(with[i].sampleCount, without[i].sampleCount) << "pixel " << i;
        for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(with[i].sum[c], without[i].sum[c], 1e-6f * std::abs(with[i].sum[c])) << "pixel " << i;
        total += without[i].sum.x;
    }
    EXPECT_GT(total, 0.0);
}

INSTANTIATE_TEST_SUITE_P(Scenes, PtLacks,
                         ::testing::Values(std::pair{"scenes/cornell-spheres.glb", gpu::SCENE_FEATURE_NO_GLOSSY},
                                           std::pair{"scenes/veach-mis.glb", gpu::SCENE_FEATURE_NO_TRANSMISSION},
                                           std::pair{"scenes/cornell-glass.glb",
                                                     gpu::SCENE_FEATURE_NO_BLEND | gpu::SCENE_FEATURE_NO_THIN |
                                                         gpu::SCENE_FEATURE_NO_SPECULAR |
                                                         gpu::SCENE_FEATURE_NO_CLEARCOAT |
                                                         gpu::SCENE_FEATURE_NO_SHEEN |
                                                         gpu::SCENE_FEATURE_NO_CLEARCOAT_NORMALS}));

// The same for request lists (PMC-IP and PMC-PT): every request writes its own result, the same
// bit for bit whatever the number of requests per invocation, for pixel-sequence requests and
// for given raster positions.
TEST_F(GpuTest, PtRequestsPerInvocationLeaveTheResultsUnchanged) {
    TileRig rig(context(), 16, 16, "methods/pt/pt");
    std::vector<gpu::SampleRequest> requests(301);
    for (uint32_t i = 0; i < requests.size(); ++i) {
        const uint32_t pixel = (i * 37u) % 256u;
        requests[i] = {pixel, i / 7u, glm::vec2(float(pixel % 16) + 0.3f, float(pixel / 16) + 0.6f)};
    }
    auto requestBuffer = vk::Buffer::storage(context(), requests, "requests");
    vk::Buffer results(context(), requests.size() * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                       "results", vk::MemoryUsage::Readback);
    rig.work.bind(gpu::PT_BINDING_REQUESTS, requestBuffer);
    rig.work.bind(gpu::PT_BINDING_RESULTS, results);
    // The list in two dispatches (requests [0, 120) and [120, 301)), P requests per invocation.
    auto render = [&](uint32_t source, uint32_t P) {
        results.fill(0);
        std::vector<std::pair<gpu::PtPush, uint32_t>> dispatches;
        for (auto [offset, count] : {std::pair<uint32_t, uint32_t>{0, 120}, {120, 181}}) {
            gpu::PtPush push = tilePush(5);
            push.source = source;
            push.flags = gpu::PT_FLAG_WRITE_RESULTS;
            push.itemsPerInvocation = P;
            push.requestOffset = offset;
            push.invocationCount = count;
            dispatches.push_back({push, invocationsFor(count, P)});
        }
        rig.run(dispatches);
        return results.download<glm::vec4>(requests.size());
    };
    for (uint32_t source : {gpu::PT_SOURCE_LIST, gpu::PT_SOURCE_POINTS}) {
        SCOPED_TRACE(source);
        const auto reference = render(source, 1);
        double total = 0.0;
        for (const glm::vec4& r : reference) total += r.w;
        EXPECT_GT(total, 0.0);  // not black
        for (uint32_t P : {3u, 8u, 64u}) {
            const auto other = render(source, P);
            for (size_t i = 0; i < requests.size(); ++i)
                ASSERT_EQ(reference[i], other[i]) << "request " << i << ", P = " << P;
        }
    }
}

}  // namespace
}  // namespace pmcr::test
