#include "vk/pipeline.h"

#include <algorithm>
#include <map>

#include "core/error.h"
#include "shared/host_device.h"
#include "vk/buffer.h"
#include "vk/check.h"
#include "vk/context.h"

namespace pmcr::vk {

const std::map<std::string, std::span<const uint32_t>>& spirvRegistry();  // generated

std::span<const uint32_t> spirv(const std::string& name) {
    const auto& registry = spirvRegistry();
    auto it = registry.find(name);
    if (it == registry.end()) throw Error("no compiled shader named '" + name + "'");
    return it->second;
}

namespace {

// The descriptor type of each binding (shared/bindings.h): the scene set has its uniform
// SceneInfo and texel buffers for the BVH, the vertices, the triangles, the materials and the
// light tables; everything else is a storage buffer.
VkDescriptorType descriptorType(DescriptorSet::Kind kind, uint32_t binding) {
    if (kind == DescriptorSet::Kind::Scene) {
        if (binding == gpu::BINDING_SCENE_INFO) return VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
        if (binding == gpu::BINDING_BVH || binding == gpu::BINDING_VERTICES ||
            binding == gpu::BINDING_TRIANGLES || binding == gpu::BINDING_MATERIALS ||
            binding == gpu::BINDING_LIGHT_GROUPS || binding == gpu::BINDING_LIGHT_EMITTERS ||
            binding == gpu::BINDING_ENV_TEXELS || binding == gpu::BINDING_ENV_ALIAS ||
            binding == gpu::BINDING_PUNCTUAL_LIGHTS || binding == gpu::BINDING_PUNCTUAL_ALIAS ||
            binding == gpu::BINDING_TEXTURE_INFOS || binding == gpu::BINDING_TEXELS ||
            binding == gpu::BINDING_TANGENTS || binding == gpu::BINDING_TRIANGLE_EMISSION)
            return VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    }
    return VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
}

VkDescriptorSetLayout createSetLayout(VkDevice device, uint32_t count, DescriptorSet::Kind kind) {
    std::vector<VkDescriptorSetLayoutBinding> bindings(count);
    for (uint32_t i = 0; i < count; ++i) {
        bindings[i].binding = i;
        bindings[i].descriptorType = descriptorType(kind, i);
        bindings[i].descriptorCount = 1;
        bindings[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
    }
    VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    info.bindingCount = count;
    info.pBindings = bindings.data();
    VkDescriptorSetLayout layout = VK_NULL_HANDLE;
    VK_CHECK(vkCreateDescriptorSetLayout(device, &info, nullptr, &layout));
    return layout;
}

}  // namespace

PipelineLayout::PipelineLayout(Context& context) : m_context(context) {
    VkDevice device = context.device();
    m_sceneSetLayout = createSetLayout(device, gpu::SCENE_BINDING_COUNT, DescriptorSet::Kind::Scene);
    m_workSetLayout = createSetLayout(device, gpu::WORK_BINDING_COUNT, DescriptorSet::Kind::Work);
    VkDescriptorSetLayout sets[] = {m_sceneSetLayout, m_workSetLayout};
    VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, gpu::PUSH_CONSTANT_BYTES};
    VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    info.setLayoutCount = 2;
    info.pSetLayouts = sets;
    info.pushConstantRangeCount = 1;
    info.pPushConstantRanges = &push;
    VK_CHECK(vkCreatePipelineLayout(device, &info, nullptr, &m_layout));
}

PipelineLayout::~PipelineLayout() {
    VkDevice device = m_context.device();
    vkDestroyPipelineLayout(device, m_layout, nullptr);
    vkDestroyDescriptorSetLayout(device, m_workSetLayout, nullptr);
    vkDestroyDescriptorSetLayout(device, m_sceneSetLayout, nullptr);
}

DescriptorSet::DescriptorSet(const PipelineLayout& layout, Kind kind, const std::string& name)
    : m_context(layout.context()), m_kind(kind) {
    VkDevice device = m_context.device();
    const uint32_t count = kind == Kind::Scene ? gpu::SCENE_BINDING_COUNT : gpu::WORK_BINDING_COUNT;
    std::vector<VkDescriptorPoolSize> sizes;
    for (uint32_t i = 0; i < count; ++i) {
        const VkDescriptorType type = descriptorType(kind, i);
        auto it = std::find_if(sizes.begin(), sizes.end(),
                               [type](const VkDescriptorPoolSize& s) { return s.type == type; });
        if (it == sizes.end()) sizes.push_back({type, 1});
        else ++it->descriptorCount;
    }
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.maxSets = 1;
    poolInfo.poolSizeCount = uint32_t(sizes.size());
    poolInfo.pPoolSizes = sizes.data();
    VK_CHECK(vkCreateDescriptorPool(device, &poolInfo, nullptr, &m_pool));
    VkDescriptorSetLayout setLayout =
        kind == Kind::Scene ? layout.sceneSetLayout() : layout.workSetLayout();
    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = m_pool;
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = &setLayout;
    VkResult result = vkAllocateDescriptorSets(device, &alloc, &m_set);
    if (result != VK_SUCCESS) {
        vkDestroyDescriptorPool(device, m_pool, nullptr);
        throwVkError(result, "vkAllocateDescriptorSets", __FILE__, __LINE__);
    }
    m_context.setName(VK_OBJECT_TYPE_DESCRIPTOR_SET, uint64_t(m_set), name.c_str());
}

DescriptorSet::~DescriptorSet() { vkDestroyDescriptorPool(m_context.device(), m_pool, nullptr); }

void DescriptorSet::bind(uint32_t binding, const Buffer& buffer) {
    const uint32_t count = m_kind == Kind::Scene ? gpu::SCENE_BINDING_COUNT : gpu::WORK_BINDING_COUNT;
    if (binding >= count) throw Error("descriptor binding " + std::to_string(binding) + " out of range");
    VkDescriptorBufferInfo info{buffer.handle(), 0, VK_WHOLE_SIZE};
    const VkBufferView view = buffer.view();
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = m_set;
    write.dstBinding = binding;
    write.descriptorCount = 1;
    write.descriptorType = descriptorType(m_kind, binding);
    if (write.descriptorType == VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER) {
        if (view == VK_NULL_HANDLE)
            throw Error("descriptor binding " + std::to_string(binding) + " needs a texel buffer");
        write.pTexelBufferView = &view;
    } else {
        write.pBufferInfo = &info;
    }
    vkUpdateDescriptorSets(m_context.device(), 1, &write, 0, nullptr);
}

Kernel::Kernel(const PipelineLayout& layout, const std::string& shaderName, uint32_t sceneFeatures,
               uint32_t kernelOptions)
    : m_context(layout.context()), m_name(shaderName) {
    Context& context = m_context;
    const VkPipelineLayout layoutHandle = layout.handle();
    m_creation = std::async(std::launch::async, [&context, layoutHandle, shaderName, sceneFeatures,
                                                 kernelOptions]() {
        auto code = spirv(shaderName);
        VkShaderModuleCreateInfo moduleInfo{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        moduleInfo.codeSize = code.size() * sizeof(uint32_t);
        moduleInfo.pCode = code.data();
        VkShaderModule module = VK_NULL_HANDLE;
        VK_CHECK(vkCreateShaderModule(context.device(), &moduleInfo, nullptr, &module));

        VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        info.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
        info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
        info.stage.module = module;
        info.stage.pName = "main";
        // Constant 0 is kSceneFeatures, 1 kKernelOptions; a shader that does not declare one
        // ignores it.
        const uint32_t constants[2] = {sceneFeatures, kernelOptions};
        const VkSpecializationMapEntry entries[2] = {{0, 0, sizeof(uint32_t)},
                                                     {1, sizeof(uint32_t), sizeof(uint32_t)}};
        const VkSpecializationInfo specialization{2, entries, sizeof(constants), constants};
        info.stage.pSpecializationInfo = &specialization;
        info.layout = layoutHandle;
        VkPipeline pipeline = VK_NULL_HANDLE;
        VkResult result = vkCreateComputePipelines(context.device(), context.pipelineCache(), 1, &info,
                                                   nullptr, &pipeline);
        vkDestroyShaderModule(context.device(), module, nullptr);
        if (result != VK_SUCCESS) throwVkError(result, "vkCreateComputePipelines", __FILE__, __LINE__);
        context.setName(VK_OBJECT_TYPE_PIPELINE, uint64_t(pipeline), shaderName.c_str());
        return pipeline;
    });
}

VkPipeline Kernel::handle() const {
    if (m_creation.valid()) m_pipeline = m_creation.get();
    return m_pipeline;
}

Kernel::~Kernel() {
    try {
        handle();
    } catch (...) {
        // A creation that failed has already been reported where the kernel was used.
    }
    if (m_pipeline) vkDestroyPipeline(m_context.device(), m_pipeline, nullptr);
}

}  // namespace pmcr::vk
