// Every VkResult goes through VK_CHECK, in every build type: a failure throws with the call's text,
// the result's name, and the place, so a user report says exactly what failed.
#pragma once

#include <vulkan/vulkan.h>

#include <stdexcept>
#include <string>

namespace iso::vk {

struct VulkanError : std::runtime_error {
    VkResult result;
    VulkanError(VkResult r, const std::string& what) : std::runtime_error(what), result(r) {}
};

const char* resultName(VkResult r);
[[noreturn]] void throwVkError(VkResult r, const char* call, const char* file, int line);

} // namespace iso::vk

#define VK_CHECK(call)                                                                                       \
    do {                                                                                                     \
        VkResult vkCheckResult_ = (call);                                                                    \
        if (vkCheckResult_ != VK_SUCCESS)                                                                    \
            ::iso::vk::throwVkError(vkCheckResult_, #call, __FILE__, __LINE__);                              \
    } while (0)
