// The Vulkan instance, the chosen physical device, its logical device and one compute queue.
#pragma once

#include <vulkan/vulkan.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace iso::vk {

struct ContextOptions {
    bool validation = false; // also switched on by ISOSCOPE_VALIDATE=1
    std::string device;      // index or case-insensitive name substring; default from ISOSCOPE_DEVICE
};

struct DeviceInfo {
    uint32_t index;
    std::string name;
    const char* type; // "discrete", "integrated", "virtual", "cpu", "other"
    uint32_t apiVersion;
};

class Context {
  public:
    explicit Context(const ContextOptions& options = {});
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    static std::vector<DeviceInfo> listDevices();

    VkInstance instance() const { return instance_; }
    VkPhysicalDevice physicalDevice() const { return physical_; }
    VkDevice device() const { return device_; }
    VkQueue queue() const { return queue_; }
    uint32_t queueFamily() const { return queueFamily_; }
    const VkPhysicalDeviceProperties& properties() const { return properties_; }
    std::string deviceName() const { return properties_.deviceName; }
    const char* deviceType() const;
    bool validationEnabled() const { return messenger_ != VK_NULL_HANDLE; }
    // Warnings and errors reported by the validation layers so far; tests require zero.
    uint64_t validationMessages() const { return validationMessages_.load(); }
    // Nanoseconds per timestamp tick, or 0 when the queue cannot write timestamps.
    double timestampPeriodNs() const { return timestampPeriodNs_; }
    uint32_t findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required) const;

    // Records commands into a one-time command buffer, submits them and waits: for uploads and
    // for frames, which are rendered one at a time anyway.
    void submitAndWait(const std::function<void(VkCommandBuffer)>& record) const;

  private:
    VkInstance instance_ = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    VkCommandPool commandPool_ = VK_NULL_HANDLE;
    VkFence fence_ = VK_NULL_HANDLE;
    uint32_t queueFamily_ = 0;
    VkPhysicalDeviceProperties properties_{};
    VkPhysicalDeviceMemoryProperties memory_{};
    double timestampPeriodNs_ = 0.0;
    std::atomic<uint64_t> validationMessages_{0};

    static VKAPI_ATTR VkBool32 VKAPI_CALL onValidationMessage(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                                              VkDebugUtilsMessageTypeFlagsEXT,
                                                              const VkDebugUtilsMessengerCallbackDataEXT*,
                                                              void*);
    void destroy();
};

} // namespace iso::vk
