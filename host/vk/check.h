// VkResult checking: every Vulkan call that returns a VkResult goes through VK_CHECK, which
// throws pmcr::Error naming the call, the result and file:line (Sascha Willems' VK_CHECK_RESULT).
#pragma once

#include <volk.h>

#include <string>

namespace pmcr::vk {

const char* resultName(VkResult result);
[[noreturn]] void throwVkError(VkResult result, const char* call, const char* file, int line);

}  // namespace pmcr::vk

#define VK_CHECK(call)                                                      \
    do {                                                                    \
        VkResult vkCheckResult_ = (call);                                   \
        if (vkCheckResult_ != VK_SUCCESS)                                   \
            ::pmcr::vk::throwVkError(vkCheckResult_, #call, __FILE__, __LINE__); \
    } while (0)
