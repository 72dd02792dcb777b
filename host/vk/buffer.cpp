#include "vk/buffer.h"

#include <cstring>
#include <utility>

#include "core/error.h"
#include "vk/check.h"
#include "vk/context.h"

namespace pmcr::vk {

namespace {

std::string mib(VkDeviceSize bytes) {
    char text[64];
    std::snprintf(text, sizeof(text), "%.1f MiB", double(bytes) / (1024.0 * 1024.0));
    return text;
}

}  // namespace

Buffer::Buffer(Context& context, VkDeviceSize size, VkBufferUsageFlags usage,
               const std::string& name, MemoryUsage memory)
    : m_context(&context), m_size(size), m_name(name) {
    const auto& limits = context.limits();
    if ((usage & VK_BUFFER_USAGE_STORAGE_BUFFER_BIT) && size > limits.maxStorageBufferRange)
        throw Error(name + " needs " + mib(size) + ", more than the device's storage buffer limit of " +
                    mib(limits.maxStorageBufferRange) + " (maxStorageBufferRange)");
    if ((usage & VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT) &&
        size / 16 > limits.maxTexelBufferElements)
        throw Error(name + " needs " + std::to_string(size / 16) +
                    " texels, more than the device's limit of " +
                    std::to_string(limits.maxTexelBufferElements) + " (maxTexelBufferElements)");
    if ((usage & VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT) && size > limits.maxUniformBufferRange)
        throw Error(name + " needs " + mib(size) + ", more than the device's uniform buffer limit");

    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = size;
    info.usage = usage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VK_CHECK(vkCreateBuffer(context.device(), &info, nullptr, &m_buffer));
    context.setName(VK_OBJECT_TYPE_BUFFER, uint64_t(m_buffer), name.c_str());

    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(context.device(), m_buffer, &req);
    uint32_t type = 0;
    if (memory == MemoryUsage::Device) {
        type = context.findMemoryType(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT,
                                      VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                          VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    } else if (memory == MemoryUsage::Upload) {
        type = context.findMemoryType(
            req.memoryTypeBits,
            VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
            VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    } else {
        type = context.findMemoryType(
            req.memoryTypeBits,
            VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
            VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
    }
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex = type;
    VkResult result = vkAllocateMemory(context.device(), &alloc, nullptr, &m_memory);
    if (result == VK_ERROR_OUT_OF_DEVICE_MEMORY || result == VK_ERROR_OUT_OF_HOST_MEMORY) {
        release();
        throw Error("out of device memory allocating " + name + " (" + mib(size) + ")");
    }
    if (result != VK_SUCCESS) {
        release();
        throwVkError(result, "vkAllocateMemory", __FILE__, __LINE__);
    }
    VK_CHECK(vkBindBufferMemory(context.device(), m_buffer, m_memory, 0));

    // Map persistently when the memory is host-visible and coherent.
    VkPhysicalDeviceMemoryProperties props;
    vkGetPhysicalDeviceMemoryProperties(context.physicalDevice(), &props);
    const VkMemoryPropertyFlags flags = props.memoryTypes[type].propertyFlags;
    const VkMemoryPropertyFlags mappable =
        VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    if ((flags & mappable) == mappable)
        VK_CHECK(vkMapMemory(context.device(), m_memory, 0, VK_WHOLE_SIZE, 0, &m_mapped));
}

Buffer::~Buffer() { release(); }

Buffer::Buffer(Buffer&& other) noexcept { *this = std::move(other); }

Buffer& Buffer::operator=(Buffer&& other) noexcept {
    if (this != &other) {
        release();
        m_context = std::exchange(other.m_context, nullptr);
        m_buffer = std::exchange(other.m_buffer, VK_NULL_HANDLE);
        m_memory = std::exchange(other.m_memory, VK_NULL_HANDLE);
        m_size = std::exchange(other.m_size, 0);
        m_mapped = std::exchange(other.m_mapped, nullptr);
        m_view = std::exchange(other.m_view, VK_NULL_HANDLE);
        m_name = std::move(other.m_name);
    }
    return *this;
}

void Buffer::release() {
    if (!m_context) return;
    VkDevice device = m_context->device();
    if (m_view) vkDestroyBufferView(device, m_view, nullptr);
    if (m_mapped) vkUnmapMemory(device, m_memory);
    if (m_buffer) vkDestroyBuffer(device, m_buffer, nullptr);
    if (m_memory) vkFreeMemory(device, m_memory, nullptr);
    m_buffer = VK_NULL_HANDLE;
    m_memory = VK_NULL_HANDLE;
    m_mapped = nullptr;
    m_view = VK_NULL_HANDLE;
    m_context = nullptr;
}

void Buffer::createView(VkFormat format) {
    VkBufferViewCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
    info.buffer = m_buffer;
    info.format = format;
    info.offset = 0;
    info.range = VK_WHOLE_SIZE;
    VK_CHECK(vkCreateBufferView(m_context->device(), &info, nullptr, &m_view));
    m_context->setName(VK_OBJECT_TYPE_BUFFER_VIEW, uint64_t(m_view), m_name.c_str());
}

void Buffer::upload(const void* data, VkDeviceSize bytes, VkDeviceSize offset) {
    if (bytes == 0) return;
    if (offset + bytes > m_size) throw Error("upload past the end of " + m_name);
    if (m_mapped) {
        std::memcpy(static_cast<char*>(m_mapped) + offset, data, bytes);
        return;
    }
    Buffer staging(*m_context, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, m_name + " (staging)",
                   MemoryUsage::Readback);
    std::memcpy(staging.mapped(), data, bytes);
    m_context->submitAndWait([&](VkCommandBuffer cmd) {
        VkBufferCopy region{0, offset, bytes};
        vkCmdCopyBuffer(cmd, staging.handle(), m_buffer, 1, &region);
    });
}

void Buffer::download(void* data, VkDeviceSize bytes, VkDeviceSize offset) const {
    if (bytes == 0) return;
    if (offset + bytes > m_size) throw Error("download past the end of " + m_name);
    if (m_mapped) {
        std::memcpy(data, static_cast<const char*>(m_mapped) + offset, bytes);
        return;
    }
    Buffer staging(*m_context, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, m_name + " (readback)",
                   MemoryUsage::Readback);
    m_context->submitAndWait([&](VkCommandBuffer cmd) {
        VkBufferCopy region{offset, 0, bytes};
        vkCmdCopyBuffer(cmd, m_buffer, staging.handle(), 1, &region);
    });
    std::memcpy(data, staging.mapped(), bytes);
}

void Buffer::fill(uint32_t value) {
    m_context->submitAndWait([&](VkCommandBuffer cmd) {
        vkCmdFillBuffer(cmd, m_buffer, 0, VK_WHOLE_SIZE, value);
    });
}

}  // namespace pmcr::vk
