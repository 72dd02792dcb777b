#include "vk/check.h"

#include <filesystem>

#include "core/error.h"

namespace pmcr::vk {

const char* resultName(VkResult result) {
    switch (result) {
#define PMCR_RESULT(r) \
    case r:            \
        return #r;
        PMCR_RESULT(VK_SUCCESS)
        PMCR_RESULT(VK_NOT_READY)
        PMCR_RESULT(VK_TIMEOUT)
        PMCR_RESULT(VK_INCOMPLETE)
        PMCR_RESULT(VK_ERROR_OUT_OF_HOST_MEMORY)
        PMCR_RESULT(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        PMCR_RESULT(VK_ERROR_INITIALIZATION_FAILED)
        PMCR_RESULT(VK_ERROR_DEVICE_LOST)
        PMCR_RESULT(VK_ERROR_MEMORY_MAP_FAILED)
        PMCR_RESULT(VK_ERROR_LAYER_NOT_PRESENT)
        PMCR_RESULT(VK_ERROR_EXTENSION_NOT_PRESENT)
        PMCR_RESULT(VK_ERROR_FEATURE_NOT_PRESENT)
        PMCR_RESULT(VK_ERROR_INCOMPATIBLE_DRIVER)
        PMCR_RESULT(VK_ERROR_TOO_MANY_OBJECTS)
        PMCR_RESULT(VK_ERROR_FORMAT_NOT_SUPPORTED)
        PMCR_RESULT(VK_ERROR_FRAGMENTED_POOL)
        PMCR_RESULT(VK_ERROR_UNKNOWN)
        PMCR_RESULT(VK_ERROR_OUT_OF_POOL_MEMORY)
#undef PMCR_RESULT
        default:
            return "VkResult(unknown)";
    }
}

void throwVkError(VkResult result, const char* call, const char* file, int line) {
    std::string message = std::string("Vulkan call ") + call + " failed with " +
                          resultName(result) + " (" +
                          std::filesystem::path(file).filename().string() + ":" +
                          std::to_string(line) + ")";
    if (result == VK_ERROR_DEVICE_LOST)
        message += "; the device was lost (a dispatch ran too long or faulted)";
    throw Error(message);
}

}  // namespace pmcr::vk
