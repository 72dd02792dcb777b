// A VkBuffer with its own memory allocation, move-only (Vulkan-Samples `vulkan_resource.h`).
// pmcr allocates a handful of large buffers, so one allocation per buffer is enough.
//
// Memory: device-local, also host-visible when the device offers that (lavapipe, resizable
// BAR), in which case upload/download map it directly; otherwise they go through a staging
// buffer. Storage buffers larger than the device's maxStorageBufferRange are refused with a
// pmcr::Error naming the buffer, so a scene too large for the device fails cleanly.
#pragma once

#include <volk.h>

#include <string>
#include <vector>

namespace pmcr::vk {

class Context;

enum class MemoryUsage {
    Device,    // GPU working memory; host access through staging when not mappable
    Readback,  // host-visible, cached where possible (results read every batch)
    Upload,    // host-visible, device-local where possible (work lists written every batch):
               // written through the mapping, without a staging copy that would wait for
               // the batches in flight
};

class Buffer {
public:
    Buffer() = default;
    Buffer(Context& context, VkDeviceSize size, VkBufferUsageFlags usage, const std::string& name,
           MemoryUsage memory = MemoryUsage::Device);
    ~Buffer();
    Buffer(Buffer&& other) noexcept;
    Buffer& operator=(Buffer&& other) noexcept;
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;

    VkBuffer handle() const { return m_buffer; }
    VkDeviceSize size() const { return m_size; }
    const std::string& name() const { return m_name; }
    bool valid() const { return m_buffer != VK_NULL_HANDLE; }
    void* mapped() const { return m_mapped; }
    // The texel view of a buffer made by texels(); VK_NULL_HANDLE otherwise.
    VkBufferView view() const { return m_view; }

    void upload(const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
    void download(void* data, VkDeviceSize bytes, VkDeviceSize offset = 0) const;
    void fill(uint32_t value);  // whole buffer, vkCmdFillBuffer

    template <class T>
    void upload(const std::vector<T>& values) {
        upload(values.data(), values.size() * sizeof(T));
    }
    template <class T>
    std::vector<T> download(size_t count) const {
        std::vector<T> values(count);
        download(values.data(), count * sizeof(T));
        return values;
    }

    // Creates a storage buffer holding `values` (at least 16 bytes, so empty arrays bind).
    template <class T>
    static Buffer storage(Context& context, const std::vector<T>& values, const std::string& name) {
        Buffer b(context, std::max<VkDeviceSize>(16, values.size() * sizeof(T)),
                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, name);
        if (!values.empty()) b.upload(values);
        return b;
    }

    // Creates a uniform texel buffer holding `values`, read by the kernels as texels of `format`
    // (16 bytes each, e.g. R32G32B32A32_UINT), with its view. Refused with a pmcr::Error
    // above the device's maxTexelBufferElements.
    template <class T>
    static Buffer texels(Context& context, const std::vector<T>& values, VkFormat format,
                         const std::string& name) {
        static_assert(sizeof(T) % 16 == 0, "texel buffers hold whole 16-byte texels");
        Buffer b(context, std::max<VkDeviceSize>(16, values.size() * sizeof(T)),
                 VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT, name);
        if (!values.empty()) b.upload(values);
        b.createView(format);
        return b;
    }

private:
    void release();
    void createView(VkFormat format);

    Context* m_context = nullptr;
    VkBuffer m_buffer = VK_NULL_HANDLE;
    VkDeviceMemory m_memory = VK_NULL_HANDLE;
    VkDeviceSize m_size = 0;
    void* m_mapped = nullptr;
    VkBufferView m_view = VK_NULL_HANDLE;
    std::string m_name;
};

}  // namespace pmcr::vk
