// Compute pipelines. Every kernel shares one pipeline layout (shared/bindings.h):
//   set 0 = scene buffers, set 1 = 16 storage buffers whose meaning each kernel defines,
//   push constants of PUSH_CONSTANT_BYTES.
// One layout means any descriptor set can be bound with any kernel, and a kernel's bindings are
// written once in its .comp and in shared/ headers, never in host code.
#pragma once

#include <volk.h>

#include <cstdint>
#include <future>
#include <span>
#include <string>
#include <vector>

namespace pmcr::vk {

class Context;
class Buffer;

// SPIR-V embedded at build time (cmake/Shaders.cmake), by name: the shader's path under shaders/
// without .comp, "methods/pt/pt", "tests/rng_test", ...
std::span<const uint32_t> spirv(const std::string& name);

class PipelineLayout {
public:
    explicit PipelineLayout(Context& context);
    ~PipelineLayout();
    PipelineLayout(const PipelineLayout&) = delete;
    PipelineLayout& operator=(const PipelineLayout&) = delete;

    VkPipelineLayout handle() const { return m_layout; }
    VkDescriptorSetLayout sceneSetLayout() const { return m_sceneSetLayout; }
    VkDescriptorSetLayout workSetLayout() const { return m_workSetLayout; }
    Context& context() const { return m_context; }

private:
    Context& m_context;
    VkDescriptorSetLayout m_sceneSetLayout = VK_NULL_HANDLE;
    VkDescriptorSetLayout m_workSetLayout = VK_NULL_HANDLE;
    VkPipelineLayout m_layout = VK_NULL_HANDLE;
};

// A descriptor set of the scene layout or the work layout, with its own small pool.
class DescriptorSet {
public:
    enum class Kind { Scene, Work };
    DescriptorSet(const PipelineLayout& layout, Kind kind, const std::string& name);
    ~DescriptorSet();
    DescriptorSet(const DescriptorSet&) = delete;
    DescriptorSet& operator=(const DescriptorSet&) = delete;

    // Points `binding` at the whole of `buffer`: uniform for the scene's binding 0, its texel
    // view for the BVH bindings (Buffer::texels), else storage.
    void bind(uint32_t binding, const Buffer& buffer);
    VkDescriptorSet handle() const { return m_set; }
    uint32_t index() const { return m_kind == Kind::Scene ? 0u : 1u; }

private:
    Context& m_context;
    Kind m_kind;
    VkDescriptorPool m_pool = VK_NULL_HANDLE;
    VkDescriptorSet m_set = VK_NULL_HANDLE;
};

class Kernel {
public:
    // The pipeline of shader `shaderName` with its specialization constant 0 (kSceneFeatures,
    // shaders/common/scene.glsl) set to `sceneFeatures` (gpu::SCENE_FEATURE_* bits) and
    // constant 1 (kKernelOptions, shaders/common/kernel_options.glsl) to `kernelOptions`
    // (gpu::KERNEL_OPTION_* bits).
    Kernel(const PipelineLayout& layout, const std::string& shaderName, uint32_t sceneFeatures = 0,
           uint32_t kernelOptions = 0);
    ~Kernel();
    Kernel(const Kernel&) = delete;
    Kernel& operator=(const Kernel&) = delete;

    // The pipeline, waiting for its creation to finish: kernels are created on threads of
    // their own, so a method's kernels (and a driver's compilation of them) proceed in
    // parallel while the host goes on; creation errors are thrown here.
    VkPipeline handle() const;
    const std::string& name() const { return m_name; }

private:
    Context& m_context;
    std::string m_name;
    mutable std::future<VkPipeline> m_creation;
    mutable VkPipeline m_pipeline = VK_NULL_HANDLE;
};

}  // namespace pmcr::vk
