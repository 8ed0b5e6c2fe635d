// A small render graph for compute frames. Passes declare which buffers and images they read and
// write; the graph culls passes whose results nobody uses, allocates transient buffers, inserts the
// barriers and image layout transitions between passes, and times every pass with timestamps.
//
// A frame is built anew each time from the scene (building is cheap), so the graph holds only the
// passes the scene needs.
#pragma once

#include "vk/resources.hpp"

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace iso::graph {

using ResourceId = uint32_t;

// How a pass touches a resource; this decides the pipeline stage, access mask and image layout.
enum class Access {
    UniformRead,   // compute shader, uniform buffer
    ShaderRead,    // compute shader, storage buffer or sampled image
    ShaderWrite,   // compute shader, storage buffer or storage image (writes, possibly reads too)
    TransferRead,  // copy source
    TransferWrite, // copy or clear destination
};

struct PassTiming {
    std::string name;
    double ms; // GPU time between the pass's timestamps; 0 when the device has no timestamps
};

// Transient buffers outlive a frame so that the next frame of the same shape reuses them.
class TransientPool {
  public:
    vk::Buffer& acquire(const vk::Context& ctx, const std::string& name, VkDeviceSize size,
                        VkBufferUsageFlags usage);
    VkDeviceSize bytes() const;

  private:
    std::map<std::string, vk::Buffer> buffers_;
};

class RenderGraph {
  public:
    class PassBuilder {
      public:
        void read(ResourceId id, Access access = Access::ShaderRead);
        void write(ResourceId id, Access access = Access::ShaderWrite);

      private:
        friend class RenderGraph;
        PassBuilder(RenderGraph& g, size_t pass) : graph_(g), pass_(pass) {}
        RenderGraph& graph_;
        size_t pass_;
    };

    // What a pass sees while it records: the Vulkan objects behind its resource ids.
    class Resources {
      public:
        VkBuffer buffer(ResourceId id) const;
        VkDeviceSize size(ResourceId id) const;
        VkImage image(ResourceId id) const;

      private:
        friend class RenderGraph;
        explicit Resources(const RenderGraph& g) : graph_(g) {}
        const RenderGraph& graph_;
    };

    using Setup = std::function<void(PassBuilder&)>;
    using Record = std::function<void(VkCommandBuffer, const Resources&)>;

    ResourceId createBuffer(const std::string& name, VkDeviceSize size, VkBufferUsageFlags usage);
    ResourceId importBuffer(const std::string& name, VkBuffer buffer, VkDeviceSize size);
    // An image owned elsewhere, currently in `layout`; the graph leaves it in whatever layout the
    // last pass needed and reports that through finalLayout().
    ResourceId importImage(const std::string& name, VkImage image, VkImageLayout layout,
                           VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT);
    void addPass(const std::string& name, const Setup& setup, Record record);
    // The resource is consumed outside the graph (read back, presented): its producers stay.
    void markOutput(ResourceId id);

    // Culls, allocates, records one command buffer, submits it and waits for it.
    std::vector<PassTiming> execute(const vk::Context& ctx, TransientPool& pool);

    std::vector<std::string> livePasses() const; // after execute(): the passes that ran, in order
    VkImageLayout finalLayout(ResourceId id) const;
    std::string graphviz() const; // for debugging: passes, resources, culled passes grey

  private:
    struct Use {
        ResourceId id;
        Access access;
        bool write;
    };
    struct Pass {
        std::string name;
        Record record;
        std::vector<Use> uses;
        bool live = false;
    };
    struct Resource {
        std::string name;
        bool transient = false;
        bool isImage = false;
        bool output = false;
        VkDeviceSize size = 0;
        VkBufferUsageFlags usage = 0;
        VkBuffer buffer = VK_NULL_HANDLE;
        VkImage image = VK_NULL_HANDLE;
        VkImageAspectFlags aspect = 0;
        VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
    };
    std::vector<Pass> passes_;
    std::vector<Resource> resources_;

    void cull();
    void recordBarriers(VkCommandBuffer cmd, const Pass& pass, std::vector<std::pair<Access, bool>>& last);
};

} // namespace iso::graph
