// The per-camera-sample kernels with PT_SOURCE_TILE (shaders/common/camera_sample_kernel.glsl):
// several passes in one dispatch (samplesPerPixel > 1, as pt does on small images) must leave
// the film exactly as one dispatch per pass does, so an image does not depend on how the
// dispatch sizer, which follows the clock, split the passes.
#include <gtest/gtest.h>

#include "gpu_test.h"
#include "render/pt_integrator.h"
#include "render/session.h"
#include "render_test.h"
#include "vk/command_batch.h"

namespace pmcr::test {
namespace {

class PtDispatch : public GpuTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(PtDispatch, SeveralPassesInOneDispatchGiveTheSameFilm) {
    const Scene& scene = testScene("scenes/cornell-spheres.glb");
    RenderSettings settings;
    settings.width = 24;
    settings.height = 24;
    RenderSession session(context(), scene, settings, 24, 24);
    const uint32_t pixels = 24 * 24;
    const uint32_t passes = 5;

    vk::Kernel kernel(session.layout(), GetParam());
    Film& film = session.film();
    vk::DescriptorSet work(session.layout(), vk::DescriptorSet::Kind::Work, "dispatch test work");
    bindTileWork(work, film, session);

    gpu::PtPush push{};
    push.source = gpu::PT_SOURCE_TILE;
    push.flags = gpu::PT_FLAG_DEPOSIT;
    push.invocationCount = pixels;
    push.seed = 7;
    push.maxDepth = 8;
    push.rrDepth = 3;
    push.lightSamples = 2;
    // Passes 3 .. 3 + passes - 1 in `perDispatch` passes per dispatch.
    auto render = [&](uint32_t perDispatch) {
        film.clear();
        vk::CommandBatch batch(session.layout());
        batch.bind(session.scene().descriptorSet());
        batch.bind(work);
        for (uint32_t pass = 0; pass < passes; pass += perDispatch) {
            push.sampleBase = 3 + pass;
            push.samplesPerPixel = std::min(perDispatch, passes - pass);
            batch.dispatch(kernel, push, pixels);
        }
        batch.submitAndWait();
        return film.download();
    };
    const auto onePerDispatch = render(1);
    const auto allInOne = render(passes);
    const auto twoPerDispatch = render(2);
    double total = 0.0;
    for (uint32_t i = 0; i < pixels; ++i) {
        ASSERT_EQ(onePerDispatch[i].sampleCount, passes) << "pixel " << i;
        for (const auto* other : {&allInOne, &twoPerDispatch}) {
            ASSERT_EQ(onePerDispatch[i].sum, (*other)[i].sum) << "pixel " << i;
            ASSERT_EQ(onePerDispatch[i].lumSum, (*other)[i].lumSum) << "pixel " << i;
            ASSERT_EQ(onePerDispatch[i].lumSqSum, (*other)[i].lumSqSum) << "pixel " << i;
            ASSERT_EQ(onePerDispatch[i].sampleCount, (*other)[i].sampleCount) << "pixel " << i;
        }
        total += onePerDispatch[i].sum.x;
    }
    EXPECT_GT(total, 0.0);  // the image is not black
}

INSTANTIATE_TEST_SUITE_P(Kernels, PtDispatch, ::testing::Values("pt", "direct"));

// pt.comp's paths in turn (PtPush::itemsPerInvocation, camera_sample_kernel.glsl): however many
// pixels each invocation takes, in whatever dispatch split, every pixel gets the same samples
// in the same order from one writer, so the film is the same bit for bit; a tile whose pixel
// count is not a multiple of P, and a tile that does not start at pixel 0, included.
TEST_F(GpuTest, PtPixelsPerInvocationLeavesTheFilmUnchanged) {
    const Scene& scene = testScene("scenes/cornell-spheres.glb");
    RenderSettings settings;
    settings.width = 23;
    settings.height = 19;
    RenderSession session(context(), scene, settings, 23, 19);
    const uint32_t pixels = 23 * 19;

    vk::Kernel kernel(session.layout(), "pt");
    Film& film = session.film();
    vk::DescriptorSet work(session.layout(), vk::DescriptorSet::Kind::Work, "paths in turn test work");
    bindTileWork(work, film, session);

    gpu::PtPush push{};
    push.source = gpu::PT_SOURCE_TILE;
    push.flags = gpu::PT_FLAG_DEPOSIT;
    push.seed = 11;
    push.maxDepth = 8;
    push.rrDepth = 3;
    push.sampleBase = 2;
    push.samplesPerPixel = 3;
    // The image in two tiles (pixels [0, 100) and [100, pixels)), P pixels per invocation.
    auto render = [&](uint32_t P) {
        film.clear();
        vk::CommandBatch batch(session.layout());
        batch.bind(session.scene().descriptorSet());
        batch.bind(work);
        push.itemsPerInvocation = P;
        for (auto [offset, count] : {std::pair<uint32_t, uint32_t>{0, 100}, {100, pixels - 100}}) {
            push.pixelOffset = offset;
            push.invocationCount = count;
            batch.dispatch(kernel, push, (count + std::max(P, 1u) - 1) / std::max(P, 1u));
        }
        batch.submitAndWait();
        return film.download();
    };
    const auto reference = render(1);
    for (uint32_t P : {0u, 3u, 8u, 64u}) {
        const auto other = render(P);
        for (uint32_t i = 0; i < pixels; ++i) {
            ASSERT_EQ(reference[i].sampleCount, 3u) << "pixel " << i;
            ASSERT_EQ(reference[i].sum, other[i].sum) << "pixel " << i << ", P = " << P;
            ASSERT_EQ(reference[i].lumSum, other[i].lumSum) << "pixel " << i << ", P = " << P;
            ASSERT_EQ(reference[i].lumSqSum, other[i].lumSqSum) << "pixel " << i << ", P = " << P;
            ASSERT_EQ(reference[i].sampleCount, other[i].sampleCount) << "pixel " << i << ", P = " << P;
        }
    }
}

// The same for request lists (PMC-IP and PMC-PT): every request writes its own result, the same
// bit for bit whatever the number of requests per invocation, for pixel-sequence requests and
// for given raster positions.
TEST_F(GpuTest, PtRequestsPerInvocationLeaveTheResultsUnchanged) {
    const Scene& scene = testScene("scenes/cornell-spheres.glb");
    RenderSettings settings;
    settings.width = 16;
    settings.height = 16;
    RenderSession session(context(), scene, settings, 16, 16);
    vk::Kernel kernel(session.layout(), "pt");
    std::vector<gpu::SampleRequest> requests(301);
    for (uint32_t i = 0; i < requests.size(); ++i) {
        const uint32_t pixel = (i * 37u) % 256u;
        requests[i] = {pixel, i / 7u, glm::vec2(float(pixel % 16) + 0.3f, float(pixel / 16) + 0.6f)};
    }
    auto requestBuffer = vk::Buffer::storage(context(), requests, "requests");
    vk::Buffer results(context(), requests.size() * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                       "results", vk::MemoryUsage::Readback);
    vk::DescriptorSet work(session.layout(), vk::DescriptorSet::Kind::Work, "requests in turn test work");
    work.bind(gpu::PT_BINDING_FILM, session.film().pixels());
    work.bind(gpu::PT_BINDING_COUNTERS, session.film().counters());
    work.bind(gpu::PT_BINDING_REQUESTS, requestBuffer);
    work.bind(gpu::PT_BINDING_RESULTS, results);

    gpu::PtPush push{};
    push.flags = gpu::PT_FLAG_WRITE_RESULTS;
    push.seed = 5;
    push.maxDepth = 8;
    push.rrDepth = 3;
    // The list in two dispatches (requests [0, 120) and [120, 301)), P requests per invocation.
    auto render = [&](uint32_t source, uint32_t P) {
        results.fill(0);
        vk::CommandBatch batch(session.layout());
        batch.bind(session.scene().descriptorSet());
        batch.bind(work);
        push.source = source;
        push.itemsPerInvocation = P;
        for (auto [offset, count] : {std::pair<uint32_t, uint32_t>{0, 120}, {120, 181}}) {
            push.requestOffset = offset;
            push.invocationCount = count;
            batch.dispatch(kernel, push, (count + std::max(P, 1u) - 1) / std::max(P, 1u));
        }
        batch.submitAndWait();
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
