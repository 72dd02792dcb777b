// Bidirectional path tracing's MIS weights on real paths (shaders/tests/bdpt_mis_test.comp): for
// every camera subpath that bdpt_subpaths traces and every vertex of it on a light, the weights
// of all the strategies that can make the path up to that vertex sum to 1, and each equals the
// weight summed plainly over the vertices (pbrt-v4's MISWeight), which bdptMisWeight's tails
// shorten. On cornell-glass (an area light; the glass sphere's delta vertices, which no strategy
// joins at) and under a sky with a sun (the environment, which camera subpaths that escape
// reach), with the power and the balance heuristic. Punctual lights cannot end a camera
// subpath; their strategies are checked statistically (tests/stat/test_bdpt.cpp BdptLights).
#include <gtest/gtest.h>

#include <cmath>

#include "gpu_test.h"
#include "render/session.h"
#include "render_test.h"
#include "vk/command_batch.h"

namespace pmcr::test {
namespace {

class BdptMis : public GpuTest {};

struct MisCheck {
    int paths = 0;       // (sample, light vertex) pairs checked
    int strategies = 0;  // weights summed
    double worstSum = 0.0;
    double worstReference = 0.0;
    int offByMore = 0;   // paths whose sum is off by more than 1e-4
};

MisCheck checkWeights(vk::Context& context, const Scene& scene, uint32_t kernelOptions) {
    const int size = 48;
    RenderSettings settings;
    settings.width = size;
    settings.height = size;
    RenderSession session(context, scene, settings, size, size);
    const uint32_t count = size * size;
    gpu::BdptPush push{};
    push.count = count;
    push.sampleIndex = 5;
    push.seed = 17;
    push.maxDepth = 8;
    push.rrDepth = 100;  // no roulette: long paths
    push.cameraStride = push.maxDepth + 2;
    push.lightStride = push.maxDepth + 1;
    push.itemsPerInvocation = 1;

    vk::Kernel subpaths(session.layout(), "methods/bdpt/bdpt_subpaths_all_lights", 0, kernelOptions);
    vk::Kernel test(session.layout(), "tests/bdpt_mis_test", 0, kernelOptions);
    const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    vk::Buffer cameraVertices(context, VkDeviceSize(count) * push.cameraStride * sizeof(gpu::BdptVertex), usage, "camera");
    vk::Buffer lightVertices(context, VkDeviceSize(count) * push.lightStride * sizeof(gpu::BdptVertex), usage, "light");
    vk::Buffer counts(context, VkDeviceSize(count) * sizeof(gpu::uvec2), usage, "counts");
    vk::Buffer queue(context, 16, usage, "queue");
    vk::Buffer results(context, VkDeviceSize(count) * push.cameraStride * sizeof(gpu::vec4), usage, "results");
    queue.fill(0);
    vk::DescriptorSet work(session.layout(), vk::DescriptorSet::Kind::Work, "bdpt mis test");
    work.bind(gpu::BDPT_BINDING_FILM, session.film().pixels());
    work.bind(gpu::BDPT_BINDING_COUNTERS, session.film().counters());
    work.bind(gpu::BDPT_BINDING_CAMERA_VERTICES, cameraVertices);
    work.bind(gpu::BDPT_BINDING_LIGHT_VERTICES, lightVertices);
    work.bind(gpu::BDPT_BINDING_COUNTS, counts);
    work.bind(gpu::BDPT_BINDING_QUEUE, queue);
    work.bind(9, results);
    vk::CommandBatch batch(session.layout());
    batch.bind(session.scene().descriptorSet());
    batch.bind(work);
    batch.dispatch(subpaths, push, count);
    batch.dispatch(test, push, count);
    batch.submitAndWait();

    MisCheck check;
    const auto r = results.download<gpu::vec4>(size_t(count) * push.cameraStride);
    for (const gpu::vec4& v : r) {
        if (v.w == 0.0f) continue;
        check.paths += 1;
        check.strategies += int(v.z);
        check.worstSum = std::max(check.worstSum, std::abs(double(v.x) - 1.0));
        if (std::abs(double(v.x) - 1.0) > 1e-4) check.offByMore += 1;
        check.worstReference = std::max(check.worstReference, double(v.y));
    }
    return check;
}

void expectWeightsSumToOne(vk::Context& context, const Scene& scene, const char* what) {
    for (uint32_t options : {0u, gpu::KERNEL_OPTION_BALANCE_HEURISTIC}) {
        const MisCheck c = checkWeights(context, scene, options);
        const char* mis = options ? "balance" : "power";
        std::printf("  %s, %s heuristic: %d paths, %d strategies, worst |sum - 1| %.3g (%d paths beyond 1e-4), "
                    "worst |w - plain sum| %.3g\n",
                    what, mis, c.paths, c.strategies, c.worstSum, c.offByMore, c.worstReference);
        EXPECT_GT(c.paths, 50) << what;  // cornell-glass: 73 of 2304 subpaths reach its small light
        EXPECT_GT(c.strategies, 2 * c.paths) << what << ": most paths can be made several ways";
        // Not exactly 1: a walk records the densities of the direction it sampled, a weight
        // evaluates those at the connection from the direction between the two hit points,
        // which differs by the ray origin's offset off the surface (the most near corners,
        // where the vertices are close): measured, 2-3% of the paths off by 1e-4 to 5e-3.
        EXPECT_LT(c.worstSum, 1e-2) << what << ", " << mis;
        EXPECT_LT(c.offByMore, c.paths / 20) << what << ", " << mis << ": paths off by more than 1e-4";
        EXPECT_LT(c.worstReference, 1e-5) << what << ", " << mis;
    }
}

TEST_F(BdptMis, WeightsOfAPathSumToOneWithAnAreaLightAndGlass) {
    expectWeightsSumToOne(context(), testScene("scenes/cornell-glass.glb"), "cornell-glass");
}

TEST_F(BdptMis, WeightsOfAPathSumToOneThroughAThinSheet) {
    Scene s = testScene("scenes/cornell-glass.glb");
    for (size_t i = 0; i < s.materials.size(); ++i)
        if (s.materialNames[i] == "GlassSphere") {
            s.materials[i].flags |= gpu::MATERIAL_THIN_WALLED;
            s.materials[i].absorption = glm::vec3(0.0f);
        }
    s.path = "cornell-thin.glb";
    finalizeScene(s);
    expectWeightsSumToOne(context(), s, "cornell-glass, thin-walled sphere");
}

TEST_F(BdptMis, WeightsOfAPathSumToOneUnderTheSky) {
    expectWeightsSumToOne(context(), cornellGlassUnderSkyAndSun(), "cornell-glass under a sky");
}

}  // namespace
}  // namespace pmcr::test
