#include "vk/resources.hpp"

#include "vk/check.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <utility>

namespace iso::vk {

namespace {

VkDeviceMemory allocate(const Context& ctx, const VkMemoryRequirements& req, VkMemoryPropertyFlags props) {
    VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    info.allocationSize = req.size;
    info.memoryTypeIndex = ctx.findMemoryType(req.memoryTypeBits, props);
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VK_CHECK(vkAllocateMemory(ctx.device(), &info, nullptr, &memory));
    return memory;
}

} // namespace

// ---- Buffer

Buffer::Buffer(const Context& ctx, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUse use)
    : device_(ctx.device()), size_(size) {
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = size;
    info.usage = usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VK_CHECK(vkCreateBuffer(device_, &info, nullptr, &buffer_));
    try {
        VkMemoryRequirements req;
        vkGetBufferMemoryRequirements(device_, buffer_, &req);
        VkMemoryPropertyFlags props = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
        if (use == MemoryUse::Upload)
            props = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        if (use == MemoryUse::Readback)
            props = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        memory_ = allocate(ctx, req, props);
        VK_CHECK(vkBindBufferMemory(device_, buffer_, memory_, 0));
        if (use != MemoryUse::Device) VK_CHECK(vkMapMemory(device_, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_));
    } catch (...) {
        reset();
        throw;
    }
}

Buffer Buffer::deviceLocalCopy(const Context& ctx, const void* data, VkDeviceSize bytes,
                               VkBufferUsageFlags usage) {
    const VkDeviceSize given = bytes;
    bytes = std::max<VkDeviceSize>(bytes, 16); // empty lists still bind a valid buffer
    Buffer staging(ctx, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::Upload);
    std::memset(staging.mapped(), 0, size_t(bytes));
    if (data && given) std::memcpy(staging.mapped(), data, size_t(given));
    Buffer out(ctx, bytes, usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::Device);
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        VkBufferCopy region{0, 0, bytes};
        vkCmdCopyBuffer(cmd, staging.handle(), out.handle(), 1, &region);
        // The fence wait orders the copy before later submissions; this barrier also makes the
        // written data visible to the shaders that read it.
        VkBufferMemoryBarrier b{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER};
        b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        b.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
        b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        b.buffer = out.handle();
        b.size = VK_WHOLE_SIZE;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0,
                             nullptr, 1, &b, 0, nullptr);
    });
    return out;
}

Buffer& Buffer::operator=(Buffer&& o) noexcept {
    if (this != &o) {
        reset();
        device_ = std::exchange(o.device_, VK_NULL_HANDLE);
        buffer_ = std::exchange(o.buffer_, VK_NULL_HANDLE);
        memory_ = std::exchange(o.memory_, VK_NULL_HANDLE);
        size_ = std::exchange(o.size_, 0);
        mapped_ = std::exchange(o.mapped_, nullptr);
    }
    return *this;
}

void Buffer::reset() {
    if (buffer_) vkDestroyBuffer(device_, buffer_, nullptr);
    if (memory_) vkFreeMemory(device_, memory_, nullptr); // unmapped implicitly
    buffer_ = VK_NULL_HANDLE;
    memory_ = VK_NULL_HANDLE;
    mapped_ = nullptr;
}

// ---- VolumeImage

VolumeImage::VolumeImage(const Context& ctx, VkFormat format, uint32_t nx, uint32_t ny, uint32_t nz,
                         std::span<const std::byte> texels)
    : device_(ctx.device()) {
    VkFormatProperties fp;
    vkGetPhysicalDeviceFormatProperties(ctx.physicalDevice(), format, &fp);
    if (!(fp.optimalTilingFeatures & VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT))
        throw std::runtime_error(ctx.deviceName() +
                                 " cannot sample 3D images of the volume's format (VkFormat " +
                                 std::to_string(int(format)) + ")");
    const auto& limits = ctx.properties().limits;
    uint32_t maxDim = limits.maxImageDimension3D;
    if (nx > maxDim || ny > maxDim || nz > maxDim)
        throw std::runtime_error("volume " + std::to_string(nx) + "x" + std::to_string(ny) + "x" +
                                 std::to_string(nz) + " exceeds " + ctx.deviceName() +
                                 "'s 3D image limit of " + std::to_string(maxDim) + " per axis");
    try {
        VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
        info.imageType = VK_IMAGE_TYPE_3D;
        info.format = format;
        info.extent = {nx, ny, nz};
        info.mipLevels = 1;
        info.arrayLayers = 1;
        info.samples = VK_SAMPLE_COUNT_1_BIT;
        info.tiling = VK_IMAGE_TILING_OPTIMAL;
        info.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
        info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
        info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
        VK_CHECK(vkCreateImage(device_, &info, nullptr, &image_));
        VkMemoryRequirements req;
        vkGetImageMemoryRequirements(device_, image_, &req);
        memory_ = allocate(ctx, req, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
        memoryBytes_ = req.size;
        VK_CHECK(vkBindImageMemory(device_, image_, memory_, 0));

        // Upload slab by slab through a bounded staging buffer, so a large scan never needs a
        // second full-size copy in host-visible memory.
        const VkDeviceSize texelBytes = texels.size() / (VkDeviceSize(nx) * ny * nz);
        const VkDeviceSize sliceBytes = texelBytes * nx * ny;
        const uint32_t slicesPerChunk =
            uint32_t(std::max<VkDeviceSize>(1, std::min<VkDeviceSize>(nz, (64u << 20) / sliceBytes)));
        Buffer staging(ctx, sliceBytes * slicesPerChunk, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::Upload);
        for (uint32_t z0 = 0; z0 < nz; z0 += slicesPerChunk) {
            uint32_t count = std::min(slicesPerChunk, nz - z0);
            std::memcpy(staging.mapped(), texels.data() + sliceBytes * z0, size_t(sliceBytes * count));
            ctx.submitAndWait([&](VkCommandBuffer cmd) {
                VkImageMemoryBarrier toDst{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
                toDst.srcAccessMask = 0;
                toDst.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
                // The first chunk discards undefined contents; later chunks keep earlier slabs.
                toDst.oldLayout =
                    z0 == 0 ? VK_IMAGE_LAYOUT_UNDEFINED : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
                toDst.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
                toDst.srcQueueFamilyIndex = toDst.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
                toDst.image = image_;
                toDst.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
                vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                                     0, 0, nullptr, 0, nullptr, 1, &toDst);
                VkBufferImageCopy region{};
                region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
                region.imageOffset = {0, 0, int32_t(z0)};
                region.imageExtent = {nx, ny, count};
                vkCmdCopyBufferToImage(cmd, staging.handle(), image_, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                                       &region);
                VkImageMemoryBarrier toRead = toDst;
                toRead.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
                toRead.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
                toRead.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
                toRead.newLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
                vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0, nullptr, 0, nullptr, 1,
                                     &toRead);
            });
        }

        VkImageViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        viewInfo.image = image_;
        viewInfo.viewType = VK_IMAGE_VIEW_TYPE_3D;
        viewInfo.format = format;
        viewInfo.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        VK_CHECK(vkCreateImageView(device_, &viewInfo, nullptr, &view_));

        VkSamplerCreateInfo samplerInfo{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
        bool linear = fp.optimalTilingFeatures & VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT;
        samplerInfo.magFilter = samplerInfo.minFilter = linear ? VK_FILTER_LINEAR : VK_FILTER_NEAREST;
        samplerInfo.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
        samplerInfo.addressModeU = samplerInfo.addressModeV = samplerInfo.addressModeW =
            VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
        samplerInfo.maxLod = 0.0f;
        VK_CHECK(vkCreateSampler(device_, &samplerInfo, nullptr, &sampler_));
    } catch (...) {
        reset();
        throw;
    }
}

VolumeImage& VolumeImage::operator=(VolumeImage&& o) noexcept {
    if (this != &o) {
        reset();
        device_ = std::exchange(o.device_, VK_NULL_HANDLE);
        image_ = std::exchange(o.image_, VK_NULL_HANDLE);
        memory_ = std::exchange(o.memory_, VK_NULL_HANDLE);
        view_ = std::exchange(o.view_, VK_NULL_HANDLE);
        sampler_ = std::exchange(o.sampler_, VK_NULL_HANDLE);
        memoryBytes_ = std::exchange(o.memoryBytes_, 0);
    }
    return *this;
}

void VolumeImage::reset() {
    if (sampler_) vkDestroySampler(device_, sampler_, nullptr);
    if (view_) vkDestroyImageView(device_, view_, nullptr);
    if (image_) vkDestroyImage(device_, image_, nullptr);
    if (memory_) vkFreeMemory(device_, memory_, nullptr);
    sampler_ = VK_NULL_HANDLE;
    view_ = VK_NULL_HANDLE;
    image_ = VK_NULL_HANDLE;
    memory_ = VK_NULL_HANDLE;
}

// ---- ComputePipeline

ComputePipeline::ComputePipeline(const Context& ctx, std::span<const uint32_t> spirv,
                                 std::vector<VkDescriptorType> bindings, std::vector<SpecConstant> constants)
    : device_(ctx.device()), bindings_(std::move(bindings)) {
    VkShaderModule module = VK_NULL_HANDLE;
    try {
        std::vector<VkDescriptorSetLayoutBinding> layoutBindings;
        std::vector<VkDescriptorPoolSize> poolSizes;
        for (uint32_t i = 0; i < bindings_.size(); ++i) {
            layoutBindings.push_back({i, bindings_[i], 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
            poolSizes.push_back({bindings_[i], 1});
        }
        VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        setInfo.bindingCount = uint32_t(layoutBindings.size());
        setInfo.pBindings = layoutBindings.data();
        VK_CHECK(vkCreateDescriptorSetLayout(device_, &setInfo, nullptr, &setLayout_));

        VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        layoutInfo.setLayoutCount = 1;
        layoutInfo.pSetLayouts = &setLayout_;
        VK_CHECK(vkCreatePipelineLayout(device_, &layoutInfo, nullptr, &layout_));

        VkShaderModuleCreateInfo moduleInfo{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        moduleInfo.codeSize = spirv.size_bytes();
        moduleInfo.pCode = spirv.data();
        VK_CHECK(vkCreateShaderModule(device_, &moduleInfo, nullptr, &module));

        std::vector<VkSpecializationMapEntry> entries;
        std::vector<uint32_t> values;
        for (const auto& c : constants) {
            entries.push_back({c.id, uint32_t(values.size() * sizeof(uint32_t)), sizeof(uint32_t)});
            values.push_back(c.value);
        }
        VkSpecializationInfo spec{uint32_t(entries.size()), entries.data(), values.size() * sizeof(uint32_t),
                                  values.data()};
        VkComputePipelineCreateInfo pipeInfo{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        pipeInfo.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
        pipeInfo.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
        pipeInfo.stage.module = module;
        pipeInfo.stage.pName = "main";
        pipeInfo.stage.pSpecializationInfo = entries.empty() ? nullptr : &spec;
        pipeInfo.layout = layout_;
        VK_CHECK(vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &pipeInfo, nullptr, &pipeline_));
        vkDestroyShaderModule(device_, module, nullptr);
        module = VK_NULL_HANDLE;

        VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        poolInfo.maxSets = 1;
        poolInfo.poolSizeCount = uint32_t(poolSizes.size());
        poolInfo.pPoolSizes = poolSizes.data();
        VK_CHECK(vkCreateDescriptorPool(device_, &poolInfo, nullptr, &pool_));
        VkDescriptorSetAllocateInfo allocInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
        allocInfo.descriptorPool = pool_;
        allocInfo.descriptorSetCount = 1;
        allocInfo.pSetLayouts = &setLayout_;
        VK_CHECK(vkAllocateDescriptorSets(device_, &allocInfo, &set_));
    } catch (...) {
        if (module) vkDestroyShaderModule(device_, module, nullptr);
        reset();
        throw;
    }
}

ComputePipeline& ComputePipeline::operator=(ComputePipeline&& o) noexcept {
    if (this != &o) {
        reset();
        device_ = std::exchange(o.device_, VK_NULL_HANDLE);
        bindings_ = std::move(o.bindings_);
        setLayout_ = std::exchange(o.setLayout_, VK_NULL_HANDLE);
        layout_ = std::exchange(o.layout_, VK_NULL_HANDLE);
        pipeline_ = std::exchange(o.pipeline_, VK_NULL_HANDLE);
        pool_ = std::exchange(o.pool_, VK_NULL_HANDLE);
        set_ = std::exchange(o.set_, VK_NULL_HANDLE);
    }
    return *this;
}

void ComputePipeline::reset() {
    if (pool_) vkDestroyDescriptorPool(device_, pool_, nullptr); // frees set_
    if (pipeline_) vkDestroyPipeline(device_, pipeline_, nullptr);
    if (layout_) vkDestroyPipelineLayout(device_, layout_, nullptr);
    if (setLayout_) vkDestroyDescriptorSetLayout(device_, setLayout_, nullptr);
    pool_ = VK_NULL_HANDLE;
    pipeline_ = VK_NULL_HANDLE;
    layout_ = VK_NULL_HANDLE;
    setLayout_ = VK_NULL_HANDLE;
    set_ = VK_NULL_HANDLE;
}

void ComputePipeline::bindBuffer(uint32_t binding, VkBuffer buffer, VkDeviceSize size) {
    VkDescriptorBufferInfo info{buffer, 0, size};
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = set_;
    write.dstBinding = binding;
    write.descriptorCount = 1;
    write.descriptorType = bindings_.at(binding);
    write.pBufferInfo = &info;
    vkUpdateDescriptorSets(device_, 1, &write, 0, nullptr);
}

void ComputePipeline::bindImage(uint32_t binding, VkImageView view, VkSampler sampler) {
    VkDescriptorImageInfo info{sampler, view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = set_;
    write.dstBinding = binding;
    write.descriptorCount = 1;
    write.descriptorType = bindings_.at(binding);
    write.pImageInfo = &info;
    vkUpdateDescriptorSets(device_, 1, &write, 0, nullptr);
}

void ComputePipeline::dispatch(VkCommandBuffer cmd, uint32_t gx, uint32_t gy, uint32_t gz) const {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &set_, 0, nullptr);
    vkCmdDispatch(cmd, gx, gy, gz);
}

// ---- QueryPool

QueryPool::QueryPool(const Context& ctx, uint32_t count) : device_(ctx.device()), count_(count) {
    VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = count;
    VK_CHECK(vkCreateQueryPool(device_, &info, nullptr, &pool_));
}

QueryPool& QueryPool::operator=(QueryPool&& o) noexcept {
    if (this != &o) {
        reset();
        device_ = std::exchange(o.device_, VK_NULL_HANDLE);
        pool_ = std::exchange(o.pool_, VK_NULL_HANDLE);
        count_ = std::exchange(o.count_, 0);
    }
    return *this;
}

void QueryPool::reset() {
    if (pool_) vkDestroyQueryPool(device_, pool_, nullptr);
    pool_ = VK_NULL_HANDLE;
}

std::vector<uint64_t> QueryPool::results() const {
    std::vector<uint64_t> out(count_);
    if (count_ == 0) return out;
    VK_CHECK(vkGetQueryPoolResults(device_, pool_, 0, count_, out.size() * sizeof(uint64_t), out.data(),
                                   sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    return out;
}

} // namespace iso::vk
