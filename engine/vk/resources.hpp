// RAII owners of the Vulkan objects the engine uses: buffers, the volume's 3D image, compute
// pipelines with their descriptor sets, and timestamp query pools. Each is move-only.
#pragma once

#include "vk/context.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace iso::vk {

enum class MemoryUse { Device, Upload, Readback };

class Buffer {
  public:
    // A device-local buffer holding `bytes` from the host, copied through a staging buffer:
    // for data the GPU reads every frame but the host changes rarely (colour maps, seed lists).
    static Buffer deviceLocalCopy(const Context& ctx, const void* data, VkDeviceSize bytes,
                                  VkBufferUsageFlags usage);

    Buffer() = default;
    Buffer(const Context& ctx, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUse use);
    ~Buffer() { reset(); }
    Buffer(Buffer&& o) noexcept { *this = std::move(o); }
    Buffer& operator=(Buffer&& o) noexcept;

    VkBuffer handle() const { return buffer_; }
    VkDeviceSize size() const { return size_; }
    void* mapped() const { return mapped_; } // host-visible buffers stay mapped
    explicit operator bool() const { return buffer_ != VK_NULL_HANDLE; }

  private:
    void reset();
    VkDevice device_ = VK_NULL_HANDLE;
    VkBuffer buffer_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    VkDeviceSize size_ = 0;
    void* mapped_ = nullptr;
};

// A 3D sampled image in SHADER_READ_ONLY_OPTIMAL layout after upload, with an unnormalised,
// clamped sampler (the ray core fetches texels; filtering is for later approximate paths).
class VolumeImage {
  public:
    VolumeImage() = default;
    VolumeImage(const Context& ctx, VkFormat format, uint32_t nx, uint32_t ny, uint32_t nz,
                std::span<const std::byte> texels);
    ~VolumeImage() { reset(); }
    VolumeImage(VolumeImage&& o) noexcept { *this = std::move(o); }
    VolumeImage& operator=(VolumeImage&& o) noexcept;

    VkImageView view() const { return view_; }
    VkSampler sampler() const { return sampler_; }
    VkDeviceSize memoryBytes() const { return memoryBytes_; }

  private:
    void reset();
    VkDevice device_ = VK_NULL_HANDLE;
    VkImage image_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    VkImageView view_ = VK_NULL_HANDLE;
    VkSampler sampler_ = VK_NULL_HANDLE;
    VkDeviceSize memoryBytes_ = 0;
};

struct SpecConstant {
    uint32_t id;
    uint32_t value; // bool, int, uint and float constants all travel as 32 bits
};

// A compute pipeline with one descriptor set whose layout is given as a list of descriptor types
// (binding i has type bindings[i]).
class ComputePipeline {
  public:
    ComputePipeline() = default;
    ComputePipeline(const Context& ctx, std::span<const uint32_t> spirv,
                    std::vector<VkDescriptorType> bindings, std::vector<SpecConstant> constants = {});
    ~ComputePipeline() { reset(); }
    ComputePipeline(ComputePipeline&& o) noexcept { *this = std::move(o); }
    ComputePipeline& operator=(ComputePipeline&& o) noexcept;

    // Points the set's bindings at resources; each call replaces what the binding saw before.
    void bindBuffer(uint32_t binding, VkBuffer buffer, VkDeviceSize size = VK_WHOLE_SIZE);
    void bindImage(uint32_t binding, VkImageView view, VkSampler sampler);
    void dispatch(VkCommandBuffer cmd, uint32_t gx, uint32_t gy, uint32_t gz) const;

  private:
    void reset();
    VkDevice device_ = VK_NULL_HANDLE;
    std::vector<VkDescriptorType> bindings_;
    VkDescriptorSetLayout setLayout_ = VK_NULL_HANDLE;
    VkPipelineLayout layout_ = VK_NULL_HANDLE;
    VkPipeline pipeline_ = VK_NULL_HANDLE;
    VkDescriptorPool pool_ = VK_NULL_HANDLE;
    VkDescriptorSet set_ = VK_NULL_HANDLE;
};

class QueryPool {
  public:
    QueryPool() = default;
    QueryPool(const Context& ctx, uint32_t count);
    ~QueryPool() { reset(); }
    QueryPool(QueryPool&& o) noexcept { *this = std::move(o); }
    QueryPool& operator=(QueryPool&& o) noexcept;
    VkQueryPool handle() const { return pool_; }
    uint32_t count() const { return count_; }
    std::vector<uint64_t> results() const;

  private:
    void reset();
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueryPool pool_ = VK_NULL_HANDLE;
    uint32_t count_ = 0;
};

} // namespace iso::vk
