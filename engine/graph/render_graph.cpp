#include "graph/render_graph.hpp"

#include "vk/check.hpp"

#include <set>
#include <sstream>
#include <stdexcept>

namespace iso::graph {

namespace {

struct Sync {
    VkPipelineStageFlags stage;
    VkAccessFlags access;
    VkImageLayout layout;
};

Sync syncOf(Access a) {
    switch (a) {
    case Access::UniformRead:
        return {VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_UNIFORM_READ_BIT, VK_IMAGE_LAYOUT_UNDEFINED};
    case Access::ShaderRead:
        return {VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT,
                VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    case Access::ShaderWrite:
        return {VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                VK_IMAGE_LAYOUT_GENERAL};
    case Access::TransferRead:
        return {VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT,
                VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL};
    case Access::TransferWrite:
        return {VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL};
    }
    throw std::logic_error("unknown graph access");
}

} // namespace

vk::Buffer& TransientPool::acquire(const vk::Context& ctx, const std::string& name, VkDeviceSize size,
                                   VkBufferUsageFlags usage) {
    auto it = buffers_.find(name);
    if (it == buffers_.end() || it->second.size() != size) {
        buffers_[name] = vk::Buffer(ctx, size, usage, vk::MemoryUse::Device);
        it = buffers_.find(name);
    }
    return it->second;
}

VkDeviceSize TransientPool::bytes() const {
    VkDeviceSize total = 0;
    for (const auto& [name, b] : buffers_) total += b.size();
    return total;
}

void RenderGraph::PassBuilder::read(ResourceId id, Access access) {
    graph_.passes_.at(pass_).uses.push_back({id, access, false});
}

void RenderGraph::PassBuilder::write(ResourceId id, Access access) {
    if (access == Access::UniformRead || access == Access::ShaderRead || access == Access::TransferRead)
        throw std::logic_error("pass '" + graph_.passes_.at(pass_).name + "' writes with a read access");
    graph_.passes_.at(pass_).uses.push_back({id, access, true});
}

VkBuffer RenderGraph::Resources::buffer(ResourceId id) const {
    const auto& r = graph_.resources_.at(id);
    if (r.isImage || !r.buffer)
        throw std::logic_error("graph resource '" + r.name + "' is not a live buffer");
    return r.buffer;
}

VkDeviceSize RenderGraph::Resources::size(ResourceId id) const {
    return graph_.resources_.at(id).size;
}

VkImage RenderGraph::Resources::image(ResourceId id) const {
    const auto& r = graph_.resources_.at(id);
    if (!r.isImage) throw std::logic_error("graph resource '" + r.name + "' is not an image");
    return r.image;
}

ResourceId RenderGraph::createBuffer(const std::string& name, VkDeviceSize size, VkBufferUsageFlags usage) {
    Resource r;
    r.name = name;
    r.transient = true;
    r.size = size;
    r.usage = usage;
    resources_.push_back(r);
    return ResourceId(resources_.size() - 1);
}

ResourceId RenderGraph::importBuffer(const std::string& name, VkBuffer buffer, VkDeviceSize size) {
    Resource r;
    r.name = name;
    r.buffer = buffer;
    r.size = size;
    resources_.push_back(r);
    return ResourceId(resources_.size() - 1);
}

ResourceId RenderGraph::importImage(const std::string& name, VkImage image, VkImageLayout layout,
                                    VkImageAspectFlags aspect) {
    Resource r;
    r.name = name;
    r.isImage = true;
    r.image = image;
    r.layout = layout;
    r.aspect = aspect;
    resources_.push_back(r);
    return ResourceId(resources_.size() - 1);
}

void RenderGraph::addPass(const std::string& name, const Setup& setup, Record record) {
    passes_.push_back({name, std::move(record), {}, false});
    PassBuilder builder(*this, passes_.size() - 1);
    setup(builder);
    for (const auto& use : passes_.back().uses)
        if (use.id >= resources_.size())
            throw std::logic_error("pass '" + name + "' uses a resource the graph does not know");
}

void RenderGraph::markOutput(ResourceId id) {
    resources_.at(id).output = true;
}

// Walks backwards from the outputs: a pass lives when it writes something that is an output or
// that a live later pass reads.
void RenderGraph::cull() {
    std::set<ResourceId> needed;
    for (ResourceId i = 0; i < resources_.size(); ++i)
        if (resources_[i].output) needed.insert(i);
    for (auto it = passes_.rbegin(); it != passes_.rend(); ++it) {
        it->live = false;
        for (const auto& use : it->uses)
            if (use.write && needed.count(use.id)) it->live = true;
        if (!it->live) continue;
        for (const auto& use : it->uses)
            if (!use.write) needed.insert(use.id);
    }
}

void RenderGraph::recordBarriers(VkCommandBuffer cmd, const Pass& pass,
                                 std::vector<std::pair<Access, bool>>& last) {
    VkPipelineStageFlags srcStages = 0, dstStages = 0;
    std::vector<VkBufferMemoryBarrier> bufferBarriers;
    std::vector<VkImageMemoryBarrier> imageBarriers;
    for (const auto& use : pass.uses) {
        Resource& r = resources_[use.id];
        Sync now = syncOf(use.access);
        auto [prevAccess, prevWrote] = last[use.id];
        bool touched = prevAccess != Access(-1);
        Sync prev = touched ? syncOf(prevAccess) : Sync{VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0, r.layout};
        bool layoutChange = r.isImage && r.layout != now.layout;
        // Read-after-read needs nothing; anything involving a write, or a layout change, needs a
        // barrier so the earlier access is finished and visible.
        if (layoutChange || (touched && (prevWrote || use.write))) {
            srcStages |= prev.stage;
            dstStages |= now.stage;
            if (r.isImage) {
                VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
                b.srcAccessMask = prevWrote ? prev.access : 0;
                b.dstAccessMask = now.access;
                b.oldLayout = r.layout;
                b.newLayout = now.layout;
                b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
                b.image = r.image;
                b.subresourceRange = {r.aspect, 0, VK_REMAINING_MIP_LEVELS, 0, VK_REMAINING_ARRAY_LAYERS};
                imageBarriers.push_back(b);
                r.layout = now.layout;
            } else {
                VkBufferMemoryBarrier b{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER};
                b.srcAccessMask = prevWrote ? prev.access : 0;
                b.dstAccessMask = now.access;
                b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
                b.buffer = r.buffer;
                b.offset = 0;
                b.size = VK_WHOLE_SIZE;
                bufferBarriers.push_back(b);
            }
        }
        // Several uses of one resource in one pass: a write wins, so the next pass waits for it.
        if (use.write || last[use.id].first == Access(-1) || !last[use.id].second)
            last[use.id] = {use.access, use.write};
    }
    if (!bufferBarriers.empty() || !imageBarriers.empty())
        vkCmdPipelineBarrier(cmd, srcStages, dstStages, 0, 0, nullptr, uint32_t(bufferBarriers.size()),
                             bufferBarriers.data(), uint32_t(imageBarriers.size()), imageBarriers.data());
}

std::vector<PassTiming> RenderGraph::execute(const vk::Context& ctx, TransientPool& pool) {
    cull();
    for (auto& r : resources_) {
        if (!r.transient) continue;
        bool used = false;
        for (const auto& p : passes_)
            for (const auto& u : p.uses) used |= p.live && resources_[u.id].name == r.name;
        if (used) r.buffer = pool.acquire(ctx, r.name, r.size, r.usage).handle();
    }
    std::vector<const Pass*> live;
    for (const auto& p : passes_)
        if (p.live) live.push_back(&p);

    const bool timed = ctx.timestampPeriodNs() > 0.0 && !live.empty();
    vk::QueryPool queries;
    if (timed) queries = vk::QueryPool(ctx, uint32_t(2 * live.size()));

    std::vector<std::pair<Access, bool>> last(resources_.size(), {Access(-1), false});
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        if (timed) vkCmdResetQueryPool(cmd, queries.handle(), 0, queries.count());
        Resources view(*this);
        for (size_t i = 0; i < live.size(); ++i) {
            recordBarriers(cmd, *live[i], last);
            // Bottom-of-pipe on both ends: each stamp is written once all earlier work is done,
            // so the difference is this pass's time alone.
            if (timed)
                vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries.handle(),
                                    uint32_t(2 * i));
            live[i]->record(cmd, view);
            if (timed)
                vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries.handle(),
                                    uint32_t(2 * i + 1));
        }
        // Outputs the host reads back must be made visible to it.
        std::vector<VkBufferMemoryBarrier> hostBarriers;
        for (ResourceId id = 0; id < resources_.size(); ++id) {
            const Resource& r = resources_[id];
            if (!r.output || r.isImage || !last[id].second) continue;
            VkBufferMemoryBarrier b{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER};
            b.srcAccessMask = syncOf(last[id].first).access;
            b.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
            b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
            b.buffer = r.buffer;
            b.size = VK_WHOLE_SIZE;
            hostBarriers.push_back(b);
        }
        if (!hostBarriers.empty())
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                                 VK_PIPELINE_STAGE_HOST_BIT, 0, 0, nullptr, uint32_t(hostBarriers.size()),
                                 hostBarriers.data(), 0, nullptr);
    });

    std::vector<PassTiming> timings;
    std::vector<uint64_t> stamps = timed ? queries.results() : std::vector<uint64_t>{};
    for (size_t i = 0; i < live.size(); ++i) {
        double ms = timed ? double(stamps[2 * i + 1] - stamps[2 * i]) * ctx.timestampPeriodNs() * 1e-6 : 0.0;
        timings.push_back({live[i]->name, ms});
    }
    return timings;
}

std::vector<std::string> RenderGraph::livePasses() const {
    std::vector<std::string> names;
    for (const auto& p : passes_)
        if (p.live) names.push_back(p.name);
    return names;
}

VkImageLayout RenderGraph::finalLayout(ResourceId id) const {
    return resources_.at(id).layout;
}

std::string RenderGraph::graphviz() const {
    std::ostringstream out;
    out << "digraph frame {\n  rankdir=LR;\n";
    for (ResourceId i = 0; i < resources_.size(); ++i)
        out << "  r" << i << " [shape=box,label=\"" << resources_[i].name << "\""
            << (resources_[i].output ? ",peripheries=2" : "") << "];\n";
    for (size_t p = 0; p < passes_.size(); ++p) {
        out << "  p" << p << " [shape=ellipse,label=\"" << passes_[p].name << "\""
            << (passes_[p].live ? "" : ",color=grey,fontcolor=grey") << "];\n";
        for (const auto& u : passes_[p].uses)
            out << (u.write ? "  p" + std::to_string(p) + " -> r" + std::to_string(u.id)
                            : "  r" + std::to_string(u.id) + " -> p" + std::to_string(p))
                << ";\n";
    }
    out << "}\n";
    return out.str();
}

} // namespace iso::graph
