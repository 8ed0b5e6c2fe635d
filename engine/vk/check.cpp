#include "vk/check.hpp"

#include <filesystem>

namespace iso::vk {

const char* resultName(VkResult r) {
    switch (r) {
#define ISO_VK_RESULT(name)                                                                                  \
    case name:                                                                                               \
        return #name;
        ISO_VK_RESULT(VK_SUCCESS)
        ISO_VK_RESULT(VK_NOT_READY)
        ISO_VK_RESULT(VK_TIMEOUT)
        ISO_VK_RESULT(VK_EVENT_SET)
        ISO_VK_RESULT(VK_EVENT_RESET)
        ISO_VK_RESULT(VK_INCOMPLETE)
        ISO_VK_RESULT(VK_ERROR_OUT_OF_HOST_MEMORY)
        ISO_VK_RESULT(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        ISO_VK_RESULT(VK_ERROR_INITIALIZATION_FAILED)
        ISO_VK_RESULT(VK_ERROR_DEVICE_LOST)
        ISO_VK_RESULT(VK_ERROR_MEMORY_MAP_FAILED)
        ISO_VK_RESULT(VK_ERROR_LAYER_NOT_PRESENT)
        ISO_VK_RESULT(VK_ERROR_EXTENSION_NOT_PRESENT)
        ISO_VK_RESULT(VK_ERROR_FEATURE_NOT_PRESENT)
        ISO_VK_RESULT(VK_ERROR_INCOMPATIBLE_DRIVER)
        ISO_VK_RESULT(VK_ERROR_TOO_MANY_OBJECTS)
        ISO_VK_RESULT(VK_ERROR_FORMAT_NOT_SUPPORTED)
        ISO_VK_RESULT(VK_ERROR_FRAGMENTED_POOL)
        ISO_VK_RESULT(VK_ERROR_UNKNOWN)
        ISO_VK_RESULT(VK_ERROR_OUT_OF_POOL_MEMORY)
        ISO_VK_RESULT(VK_ERROR_SURFACE_LOST_KHR)
        ISO_VK_RESULT(VK_ERROR_NATIVE_WINDOW_IN_USE_KHR)
        ISO_VK_RESULT(VK_SUBOPTIMAL_KHR)
        ISO_VK_RESULT(VK_ERROR_OUT_OF_DATE_KHR)
#undef ISO_VK_RESULT
    default:
        return "VK_RESULT_UNKNOWN";
    }
}

void throwVkError(VkResult r, const char* call, const char* file, int line) {
    throw VulkanError(r, std::string("Vulkan call failed with ") + resultName(r) + ": " + call + " (" +
                             std::filesystem::path(file).filename().string() + ":" + std::to_string(line) +
                             ")");
}

} // namespace iso::vk
