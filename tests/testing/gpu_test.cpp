#include "gpu_test.h"

#include <cstdlib>
#include <cstring>
#include <map>

#include "shared/host_device.h"

namespace pmcr::test {

namespace {
bool validationRequested() {
    const char* env = std::getenv("PMCR_VALIDATE");
    return !(env && std::strcmp(env, "0") == 0);
}
}  // namespace

vk::Context& gpuContext() {
    static std::unique_ptr<vk::Context> context = [] {
        vk::ContextOptions options;
        options.validate = validationRequested();
        if (const char* device = std::getenv("PMCR_TEST_DEVICE")) options.device = device;
        return std::make_unique<vk::Context>(options);
    }();
    return *context;
}

vk::PipelineLayout& gpuLayout() {
    static std::unique_ptr<vk::PipelineLayout> layout =
        std::make_unique<vk::PipelineLayout>(gpuContext());
    return *layout;
}

vk::Kernel& gpuKernel(const std::string& shader) {
    // Pipelines are built once per binary: lavapipe compiles each one with LLVM (tens of ms).
    // The layout (and context) exist before the cache, so they outlive it at exit.
    vk::PipelineLayout& layout = gpuLayout();
    static std::map<std::string, std::unique_ptr<vk::Kernel>> kernels;
    auto& slot = kernels[shader];
    if (!slot) slot = std::make_unique<vk::Kernel>(layout, shader);
    return *slot;
}

void GpuTest::SetUp() { context().clearValidationMessages(); }

void GpuTest::TearDown() {
    auto messages = context().validationMessages();
    EXPECT_TRUE(messages.empty()) << messages.size() << " validation message(s), first: "
                                  << (messages.empty() ? "" : messages.front());
    context().clearValidationMessages();
}

void GpuTest::runRaw(const std::string& shader, const void* push, uint32_t pushBytes,
                     uint32_t invocations, std::initializer_list<const vk::Buffer*> buffers,
                     const vk::DescriptorSet* scene) {
    const vk::Kernel& kernel = gpuKernel(shader);
    vk::DescriptorSet work(layout(), vk::DescriptorSet::Kind::Work, shader + " work set");
    uint32_t binding = 0;
    for (const vk::Buffer* buffer : buffers) {
        if (buffer) work.bind(binding, *buffer);
        ++binding;
    }
    vk::CommandBatch batch(layout());
    if (scene) batch.bind(*scene);
    batch.bind(work);
    batch.dispatch(kernel, push, pushBytes, invocations);
    batch.submitAndWait();
}

vk::Buffer GpuTest::zeros(size_t bytes, const std::string& name) {
    vk::Buffer b(context(), std::max<size_t>(bytes, 16), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, name);
    b.fill(0);
    return b;
}

}  // namespace pmcr::test
