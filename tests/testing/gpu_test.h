// Fixture for tests that dispatch kernels: one Vulkan context per test binary, created with
// the Khronos validation layer (synchronization validation included). Any validation message
// emitted during a test fails that test.
#pragma once

#include <gtest/gtest.h>

#include <initializer_list>
#include <memory>
#include <string>
#include <utility>

#include "vk/buffer.h"
#include "vk/command_batch.h"
#include "vk/context.h"
#include "vk/pipeline.h"

namespace pmcr::test {

// The shared context (validation on unless PMCR_VALIDATE=0 in the environment).
vk::Context& gpuContext();
vk::PipelineLayout& gpuLayout();
// The pipeline of a kernel of the shared layout, built on first use and kept.
vk::Kernel& gpuKernel(const std::string& shader);

class GpuTest : public ::testing::Test {
protected:
    void SetUp() override;
    void TearDown() override;

    vk::Context& context() { return gpuContext(); }
    vk::PipelineLayout& layout() { return gpuLayout(); }

    // Runs `shader` once over `invocations` with the given work-set buffers bound at their
    // index in `buffers` (binding i = buffers[i]; nullptr entries stay unbound), and `scene`
    // (e.g. GpuScene::descriptorSet()) as set 0 when given.
    template <class Push>
    void run(const std::string& shader, const Push& push, uint32_t invocations,
             std::initializer_list<const vk::Buffer*> buffers,
             const vk::DescriptorSet* scene = nullptr) {
        runRaw(shader, &push, sizeof(Push), invocations, buffers, scene);
    }
    void runRaw(const std::string& shader, const void* push, uint32_t pushBytes,
                uint32_t invocations, std::initializer_list<const vk::Buffer*> buffers,
                const vk::DescriptorSet* scene = nullptr);

    template <class T>
    vk::Buffer storage(const std::vector<T>& values, const std::string& name = "test buffer") {
        return vk::Buffer::storage(context(), values, name);
    }
    vk::Buffer zeros(size_t bytes, const std::string& name = "test output");
};

}  // namespace pmcr::test
