// The Vulkan instance, the chosen physical device, its logical device and compute queue.
//
// Device choice: a discrete GPU, else an integrated one, else a virtual one, else the CPU device
// (Mesa lavapipe), among devices that have every feature pmcr needs; `--device <index|name
// substring>` overrides. The features are checked at start-up and a missing one fails with a
// message naming it.
#pragma once

#include <volk.h>

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <tuple>
#include <vector>

#include "vk/device_activity.h"

namespace pmcr::vk {

class PipelineLayout;
class PipelineCache;
class Kernel;

struct ContextOptions {
    bool validate = false;       // enable VK_LAYER_KHRONOS_validation (+ synchronization checks)
    std::string device;          // "" = automatic; a decimal index; or a name substring
    bool printValidation = true; // echo validation messages to stderr as they arrive
};

struct DeviceDescription {
    uint32_t index = 0;
    std::string name;
    std::string type;            // "discrete GPU", "integrated GPU", "CPU", ...
    std::string apiVersion;
    std::string driver;
    std::vector<std::string> missing;  // required features/extensions it lacks; empty = usable
};

class Context {
public:
    explicit Context(const ContextOptions& options = {});
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    // Every physical device and whether pmcr can use it (for --list-devices).
    static std::vector<DeviceDescription> listDevices();

    VkInstance instance() const { return m_instance; }
    VkPhysicalDevice physicalDevice() const { return m_physicalDevice; }
    VkDevice device() const { return m_device; }
    VkQueue queue() const { return m_queue; }
    uint32_t queueFamily() const { return m_queueFamily; }
    const VkPhysicalDeviceProperties& properties() const { return m_properties; }
    const VkPhysicalDeviceLimits& limits() const { return m_properties.limits; }
    std::string deviceName() const { return m_properties.deviceName; }
    std::string deviceTypeName() const;
    bool isCpuDevice() const { return m_properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU; }
    bool validationEnabled() const { return m_validate; }
    bool timestampsSupported() const { return m_timestampValidBits > 0; }
    uint32_t timestampValidBits() const { return m_timestampValidBits; }

    // Validation messages (warnings and errors) received so far. Tests require none.
    std::vector<std::string> validationMessages() const;
    void clearValidationMessages();

    uint32_t findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required,
                            VkMemoryPropertyFlags preferred) const;

    // Records commands into a one-time command buffer, submits it and waits for completion.
    void submitAndWait(const std::function<void(VkCommandBuffer)>& record);
    // Waits until every submission to the queue has completed (batches in flight included).
    void waitIdle() const;
    VkCommandPool commandPool() const { return m_commandPool; }
    DeviceActivity& activity() { return m_activity; }
    // submitAndWait()s (staging copies, fills) made while batches were in flight: each waited
    // for those batches too (a fence covers every submission before it), draining the queue.
    uint64_t queueDrains() const { return m_queueDrains; }
    const DeviceActivity& activity() const { return m_activity; }
    // The on-disk pipeline cache every kernel is created through (vk/pipeline_cache.h).
    VkPipelineCache pipelineCache() const;
    // Wall time spent creating pipelines (kernel()) in this context so far.
    double pipelineSeconds() const { return m_pipelineSeconds; }

    // Names a Vulkan object for validation messages and debuggers (no-op without validation).
    void setName(VkObjectType type, uint64_t handle, const char* name) const;

    // The one pipeline layout every kernel uses (shared/bindings.h), and each kernel's pipeline,
    // built on first use and kept: lavapipe translates SPIR-V on every pipeline creation (tenths
    // of a second for the path tracer), so a process that renders many times builds each once.
    const PipelineLayout& layout();
    // `sceneFeatures` and `kernelOptions` specialize it (Kernel): one pipeline per shader,
    // feature set and option set.
    const Kernel& kernel(const std::string& shaderName, uint32_t sceneFeatures = 0,
                         uint32_t kernelOptions = 0);

private:
    void destroy();
    static VKAPI_ATTR VkBool32 VKAPI_CALL debugCallback(
        VkDebugUtilsMessageSeverityFlagBitsEXT severity,
        VkDebugUtilsMessageTypeFlagsEXT types,
        const VkDebugUtilsMessengerCallbackDataEXT* data, void* user);

    bool m_validate = false;
    bool m_printValidation = true;
    VkInstance m_instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT m_messenger = VK_NULL_HANDLE;
    VkPhysicalDevice m_physicalDevice = VK_NULL_HANDLE;
    VkPhysicalDeviceProperties m_properties{};
    VkPhysicalDeviceMemoryProperties m_memoryProperties{};
    VkDevice m_device = VK_NULL_HANDLE;
    VkQueue m_queue = VK_NULL_HANDLE;
    uint32_t m_queueFamily = 0;
    uint32_t m_timestampValidBits = 0;
    VkCommandPool m_commandPool = VK_NULL_HANDLE;

    mutable std::mutex m_messageMutex;
    std::vector<std::string> m_messages;

    DeviceActivity m_activity;
    uint64_t m_queueDrains = 0;
    mutable std::unique_ptr<PipelineCache> m_pipelineCache;
    double m_pipelineSeconds = 0.0;
    std::unique_ptr<PipelineLayout> m_layout;
    std::map<std::tuple<std::string, uint32_t, uint32_t>, std::unique_ptr<Kernel>> m_kernels;
};

}  // namespace pmcr::vk
