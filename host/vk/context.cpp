#include "vk/context.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>

#include "core/error.h"
#include "vk/check.h"
#include "vk/pipeline.h"
#include "vk/pipeline_cache.h"

namespace pmcr::vk {

namespace {

const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

std::string versionString(uint32_t v) {
    return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) +
           "." + std::to_string(VK_API_VERSION_PATCH(v));
}

const char* typeName(VkPhysicalDeviceType type) {
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
            return "discrete GPU";
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
            return "integrated GPU";
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
            return "virtual GPU";
        case VK_PHYSICAL_DEVICE_TYPE_CPU:
            return "CPU";
        default:
            return "other";
    }
}

// Lower is better: the automatic choice takes the best-ranked usable device.
int typeRank(VkPhysicalDeviceType type) {
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
            return 0;
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
            return 1;
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
            return 2;
        case VK_PHYSICAL_DEVICE_TYPE_CPU:
            return 3;
        default:
            return 4;
    }
}

bool hasDeviceExtension(VkPhysicalDevice pd, const char* name) {
    uint32_t count = 0;
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &count, nullptr);
    std::vector<VkExtensionProperties> exts(count);
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &count, exts.data());
    return std::any_of(exts.begin(), exts.end(),
                       [&](const VkExtensionProperties& e) { return !strcmp(e.extensionName, name); });
}

int computeQueueFamily(VkPhysicalDevice pd) {
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &count, families.data());
    // Prefer a family that also does graphics (the "universal" queue has the most reliable
    // timestamps); any compute family works.
    int fallback = -1;
    for (uint32_t i = 0; i < count; ++i) {
        if (!(families[i].queueFlags & VK_QUEUE_COMPUTE_BIT)) continue;
        if (families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) return int(i);
        if (fallback < 0) fallback = int(i);
    }
    return fallback;
}

// The features pmcr's kernels use. Returns the names of those `pd` lacks.
std::vector<std::string> missingFeatures(VkPhysicalDevice pd) {
    std::vector<std::string> missing;
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(pd, &props);
    if (props.apiVersion < VK_API_VERSION_1_2) {
        missing.push_back("Vulkan 1.2 (device offers " + versionString(props.apiVersion) + ")");
        return missing;
    }
    if (computeQueueFamily(pd) < 0) missing.push_back("a compute queue");
    const bool atomicFloatExt = hasDeviceExtension(pd, VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);
    if (!atomicFloatExt) missing.push_back(VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);

    VkPhysicalDeviceShaderAtomicFloatFeaturesEXT atomicFloat{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT};
    VkPhysicalDeviceVulkan12Features v12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    if (atomicFloatExt) v12.pNext = &atomicFloat;
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &v12};
    vkGetPhysicalDeviceFeatures2(pd, &features);
    if (!features.features.shaderInt64) missing.push_back("shaderInt64");
    if (!v12.scalarBlockLayout) missing.push_back("scalarBlockLayout");
    if (!v12.shaderBufferInt64Atomics) missing.push_back("shaderBufferInt64Atomics");
    if (atomicFloatExt && !atomicFloat.shaderBufferFloat32AtomicAdd)
        missing.push_back("shaderBufferFloat32AtomicAdd");

    VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
    VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &subgroup};
    vkGetPhysicalDeviceProperties2(pd, &props2);
    const VkSubgroupFeatureFlags needOps =
        VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_ARITHMETIC_BIT;
    if (!(subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) ||
        (subgroup.supportedOperations & needOps) != needOps)
        missing.push_back("subgroup arithmetic in compute shaders");
    return missing;
}

std::vector<VkPhysicalDevice> enumeratePhysicalDevices(VkInstance instance) {
    uint32_t count = 0;
    VK_CHECK(vkEnumeratePhysicalDevices(instance, &count, nullptr));
    std::vector<VkPhysicalDevice> devices(count);
    VK_CHECK(vkEnumeratePhysicalDevices(instance, &count, devices.data()));
    return devices;
}

bool layerAvailable(const char* name) {
    uint32_t count = 0;
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> layers(count);
    vkEnumerateInstanceLayerProperties(&count, layers.data());
    return std::any_of(layers.begin(), layers.end(),
                       [&](const VkLayerProperties& l) { return !strcmp(l.layerName, name); });
}

void initializeLoader() {
    static const VkResult result = volkInitialize();
    if (result != VK_SUCCESS)
        throw Error("no Vulkan loader found (install libvulkan1 and a driver, e.g. mesa-vulkan-drivers)");
}

bool instanceExtensionAvailable(const char* name) {
    uint32_t count = 0;
    vkEnumerateInstanceExtensionProperties(nullptr, &count, nullptr);
    std::vector<VkExtensionProperties> exts(count);
    vkEnumerateInstanceExtensionProperties(nullptr, &count, exts.data());
    return std::any_of(exts.begin(), exts.end(),
                       [&](const VkExtensionProperties& e) { return !strcmp(e.extensionName, name); });
}

// volk keeps one set of process-wide function pointers. Every instance pmcr creates enables the
// same extensions and loads the loader's dispatching trampolines (volkLoadInstance, never
// volkLoadDevice), so the pointers stay valid for every instance and device alive at once
// (e.g. --list-devices' temporary instance beside a render's).
VkInstance createInstance(bool validate) {
    initializeLoader();
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "pmcr";
    app.applicationVersion = VK_MAKE_API_VERSION(0, 0, 1, 0);
    app.pEngineName = "pmcr";
    app.apiVersion = VK_API_VERSION_1_2;

    std::vector<const char*> layers;
    std::vector<const char*> extensions;
    if (validate) {
        if (!layerAvailable(kValidationLayer))
            throw Error(std::string("--validate needs the ") + kValidationLayer +
                        " layer (install vulkan-validationlayers)");
        layers.push_back(kValidationLayer);
        extensions.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
    }
    if (instanceExtensionAvailable(VK_EXT_DEBUG_UTILS_EXTENSION_NAME))
        extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    else if (validate)
        throw Error(std::string("--validate needs the ") + VK_EXT_DEBUG_UTILS_EXTENSION_NAME +
                    " instance extension");

    // Synchronization validation catches missing barriers between dependent dispatches.
    VkValidationFeatureEnableEXT enables[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
    VkValidationFeaturesEXT validationFeatures{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    validationFeatures.enabledValidationFeatureCount = 1;
    validationFeatures.pEnabledValidationFeatures = enables;

    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pNext = validate ? &validationFeatures : nullptr;
    info.pApplicationInfo = &app;
    info.enabledLayerCount = uint32_t(layers.size());
    info.ppEnabledLayerNames = layers.data();
    info.enabledExtensionCount = uint32_t(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    VkInstance instance = VK_NULL_HANDLE;
    VK_CHECK(vkCreateInstance(&info, nullptr, &instance));
    volkLoadInstance(instance);
    return instance;
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

}  // namespace

std::vector<DeviceDescription> Context::listDevices() {
    VkInstance instance = createInstance(false);
    std::vector<DeviceDescription> result;
    try {
        auto devices = enumeratePhysicalDevices(instance);
        for (uint32_t i = 0; i < devices.size(); ++i) {
            VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
            VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &driver};
            vkGetPhysicalDeviceProperties2(devices[i], &props);
            DeviceDescription d;
            d.index = i;
            d.name = props.properties.deviceName;
            d.type = typeName(props.properties.deviceType);
            d.apiVersion = versionString(props.properties.apiVersion);
            d.driver = std::string(driver.driverName) + " " + driver.driverInfo;
            d.missing = missingFeatures(devices[i]);
            result.push_back(d);
        }
    } catch (...) {
        vkDestroyInstance(instance, nullptr);
        throw;
    }
    vkDestroyInstance(instance, nullptr);
    return result;
}

Context::Context(const ContextOptions& options)
    : m_validate(options.validate), m_printValidation(options.printValidation) {
    m_instance = createInstance(m_validate);
    try {
        if (m_validate) {
            VkDebugUtilsMessengerCreateInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
            info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                   VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
            info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                               VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
            info.pfnUserCallback = &Context::debugCallback;
            info.pUserData = this;
            VK_CHECK(vkCreateDebugUtilsMessengerEXT(m_instance, &info, nullptr, &m_messenger));
        }

        // Choose the physical device.
        auto devices = enumeratePhysicalDevices(m_instance);
        if (devices.empty())
            throw Error("no Vulkan device found (install a driver, e.g. mesa-vulkan-drivers for lavapipe)");
        int chosen = -1;
        if (!options.device.empty()) {
            const bool isIndex = std::all_of(options.device.begin(), options.device.end(),
                                             [](unsigned char c) { return std::isdigit(c); });
            for (size_t i = 0; i < devices.size() && chosen < 0; ++i) {
                VkPhysicalDeviceProperties p;
                vkGetPhysicalDeviceProperties(devices[i], &p);
                if (isIndex ? std::stoul(options.device) == i
                            : lower(p.deviceName).find(lower(options.device)) != std::string::npos)
                    chosen = int(i);
            }
            if (chosen < 0)
                throw Error("--device " + options.device +
                            ": no such Vulkan device (see pmcr --list-devices)");
            auto missing = missingFeatures(devices[chosen]);
            if (!missing.empty()) {
                VkPhysicalDeviceProperties p;
                vkGetPhysicalDeviceProperties(devices[chosen], &p);
                std::string list;
                for (auto& m : missing) list += (list.empty() ? "" : ", ") + m;
                throw Error(std::string("device '") + p.deviceName + "' lacks what pmcr needs: " + list);
            }
        } else {
            int bestRank = 1 << 30;
            std::string rejected;
            for (size_t i = 0; i < devices.size(); ++i) {
                VkPhysicalDeviceProperties p;
                vkGetPhysicalDeviceProperties(devices[i], &p);
                auto missing = missingFeatures(devices[i]);
                if (!missing.empty()) {
                    rejected += std::string(rejected.empty() ? "" : "; ") + p.deviceName + " lacks " + missing[0];
                    continue;
                }
                if (typeRank(p.deviceType) < bestRank) {
                    bestRank = typeRank(p.deviceType);
                    chosen = int(i);
                }
            }
            if (chosen < 0) throw Error("no usable Vulkan device: " + rejected);
        }
        m_physicalDevice = devices[chosen];
        vkGetPhysicalDeviceProperties(m_physicalDevice, &m_properties);
        vkGetPhysicalDeviceMemoryProperties(m_physicalDevice, &m_memoryProperties);
        m_queueFamily = uint32_t(computeQueueFamily(m_physicalDevice));
        {
            uint32_t count = 0;
            vkGetPhysicalDeviceQueueFamilyProperties(m_physicalDevice, &count, nullptr);
            std::vector<VkQueueFamilyProperties> families(count);
            vkGetPhysicalDeviceQueueFamilyProperties(m_physicalDevice, &count, families.data());
            m_timestampValidBits = families[m_queueFamily].timestampValidBits;
            if (!m_properties.limits.timestampComputeAndGraphics) m_timestampValidBits = 0;
        }

        // Create the logical device with exactly the features pmcr uses.
        float priority = 1.0f;
        VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
        queueInfo.queueFamilyIndex = m_queueFamily;
        queueInfo.queueCount = 1;
        queueInfo.pQueuePriorities = &priority;

        VkPhysicalDeviceShaderAtomicFloatFeaturesEXT atomicFloat{
            VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT};
        atomicFloat.shaderBufferFloat32AtomicAdd = VK_TRUE;
        VkPhysicalDeviceVulkan12Features v12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
        v12.pNext = &atomicFloat;
        v12.scalarBlockLayout = VK_TRUE;
        v12.shaderBufferInt64Atomics = VK_TRUE;
        VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &v12};
        features.features.shaderInt64 = VK_TRUE;

        const char* extensions[] = {VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME};
        VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &features};
        info.queueCreateInfoCount = 1;
        info.pQueueCreateInfos = &queueInfo;
        info.enabledExtensionCount = 1;
        info.ppEnabledExtensionNames = extensions;
        VK_CHECK(vkCreateDevice(m_physicalDevice, &info, nullptr, &m_device));
        vkGetDeviceQueue(m_device, m_queueFamily, 0, &m_queue);

        VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        poolInfo.queueFamilyIndex = m_queueFamily;
        VK_CHECK(vkCreateCommandPool(m_device, &poolInfo, nullptr, &m_commandPool));
    } catch (...) {
        destroy();
        throw;
    }
}

Context::~Context() { destroy(); }

void Context::destroy() {
    if (m_device) {
        vkDeviceWaitIdle(m_device);
        m_kernels.clear();  // waits for creations still running
        if (m_pipelineCache) m_pipelineCache->save();
        m_pipelineCache.reset();
        m_layout.reset();
        if (m_commandPool) vkDestroyCommandPool(m_device, m_commandPool, nullptr);
        vkDestroyDevice(m_device, nullptr);
        m_device = VK_NULL_HANDLE;
        m_commandPool = VK_NULL_HANDLE;
    }
    if (m_messenger) {
        vkDestroyDebugUtilsMessengerEXT(m_instance, m_messenger, nullptr);
        m_messenger = VK_NULL_HANDLE;
    }
    if (m_instance) {
        vkDestroyInstance(m_instance, nullptr);
        m_instance = VK_NULL_HANDLE;
    }
}

std::string Context::deviceTypeName() const { return typeName(m_properties.deviceType); }

std::vector<std::string> Context::validationMessages() const {
    std::lock_guard lock(m_messageMutex);
    return m_messages;
}

void Context::clearValidationMessages() {
    std::lock_guard lock(m_messageMutex);
    m_messages.clear();
}

VKAPI_ATTR VkBool32 VKAPI_CALL Context::debugCallback(
    VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT types,
    const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    auto* self = static_cast<Context*>(user);
    // Loader chatter (general, warning level) is not a validation failure.
    if ((types & VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT) == 0 &&
        severity < VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT)
        return VK_FALSE;
    std::string message = std::string(severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT
                                          ? "validation error: "
                                          : "validation warning: ") +
                          (data && data->pMessage ? data->pMessage : "");
    {
        std::lock_guard lock(self->m_messageMutex);
        self->m_messages.push_back(message);
    }
    if (self->m_printValidation) std::fprintf(stderr, "%s\n", message.c_str());
    return VK_FALSE;
}

uint32_t Context::findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required,
                                 VkMemoryPropertyFlags preferred) const {
    // First a type with required | preferred, then one with required alone.
    for (VkMemoryPropertyFlags want : {required | preferred, required}) {
        for (uint32_t i = 0; i < m_memoryProperties.memoryTypeCount; ++i) {
            if ((typeBits & (1u << i)) &&
                (m_memoryProperties.memoryTypes[i].propertyFlags & want) == want)
                return i;
        }
    }
    throw Error("no Vulkan memory type with the required properties");
}

void Context::submitAndWait(const std::function<void(VkCommandBuffer)>& record) {
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = m_commandPool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VK_CHECK(vkAllocateCommandBuffers(m_device, &alloc, &cmd));
    VkFence fence = VK_NULL_HANDLE;
    try {
        VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        VK_CHECK(vkBeginCommandBuffer(cmd, &begin));
        record(cmd);
        VK_CHECK(vkEndCommandBuffer(cmd));
        VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        VK_CHECK(vkCreateFence(m_device, &fenceInfo, nullptr, &fence));
        VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        submit.commandBufferCount = 1;
        submit.pCommandBuffers = &cmd;
        const auto submittedAt = DeviceActivity::Clock::now();
        if (m_activity.inFlight() > 0) ++m_queueDrains;
        VK_CHECK(vkQueueSubmit(m_queue, 1, &submit, fence));
        m_activity.submitted(submittedAt);
        VK_CHECK(vkWaitForFences(m_device, 1, &fence, VK_TRUE, UINT64_MAX));
        m_activity.completed(submittedAt, false, -1.0);
    } catch (...) {
        if (fence) vkDestroyFence(m_device, fence, nullptr);
        vkFreeCommandBuffers(m_device, m_commandPool, 1, &cmd);
        throw;
    }
    vkDestroyFence(m_device, fence, nullptr);
    vkFreeCommandBuffers(m_device, m_commandPool, 1, &cmd);
}

void Context::waitIdle() const { VK_CHECK(vkQueueWaitIdle(m_queue)); }

const PipelineLayout& Context::layout() {
    if (!m_layout) m_layout = std::make_unique<PipelineLayout>(*this);
    return *m_layout;
}

const Kernel& Context::kernel(const std::string& shaderName, uint32_t sceneFeatures,
                              uint32_t kernelOptions) {
    auto& slot = m_kernels[{shaderName, sceneFeatures, kernelOptions}];
    if (!slot) {
        const auto start = std::chrono::steady_clock::now();
        pipelineCache();  // created here, before the creation threads share it
        slot = std::make_unique<Kernel>(layout(), shaderName, sceneFeatures, kernelOptions);
        m_pipelineSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    return *slot;
}

VkPipelineCache Context::pipelineCache() const {
    if (!m_pipelineCache) m_pipelineCache = std::make_unique<PipelineCache>(m_device, m_properties);
    return m_pipelineCache->handle();
}

void Context::setName(VkObjectType type, uint64_t handle, const char* name) const {
    if (!m_validate || !vkSetDebugUtilsObjectNameEXT || !name) return;
    VkDebugUtilsObjectNameInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
    info.objectType = type;
    info.objectHandle = handle;
    info.pObjectName = name;
    vkSetDebugUtilsObjectNameEXT(m_device, &info);
}

}  // namespace pmcr::vk
