// The render graph on a real device: culling, barriers between passes, image layout transitions
// and per-pass timestamps, observed through results and the validation layers.
#include "gpu_fixture.hpp"

#include "graph/render_graph.hpp"
#include "vk/check.hpp"

#include <doctest/doctest.h>

#include <cstring>

using namespace iso;

namespace {

// A 2D image the graph can clear and copy from, owned by the test.
struct TestImage {
    VkDevice device;
    VkImage image = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    explicit TestImage(const vk::Context& ctx, uint32_t w, uint32_t h) : device(ctx.device()) {
        VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
        info.imageType = VK_IMAGE_TYPE_2D;
        info.format = VK_FORMAT_R32_UINT;
        info.extent = {w, h, 1};
        info.mipLevels = info.arrayLayers = 1;
        info.samples = VK_SAMPLE_COUNT_1_BIT;
        info.tiling = VK_IMAGE_TILING_OPTIMAL;
        info.usage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
        VK_CHECK(vkCreateImage(device, &info, nullptr, &image));
        VkMemoryRequirements req;
        vkGetImageMemoryRequirements(device, image, &req);
        VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        alloc.allocationSize = req.size;
        alloc.memoryTypeIndex = ctx.findMemoryType(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
        VK_CHECK(vkAllocateMemory(device, &alloc, nullptr, &memory));
        VK_CHECK(vkBindImageMemory(device, image, memory, 0));
    }
    ~TestImage() {
        vkDestroyImage(device, image, nullptr);
        vkFreeMemory(device, memory, nullptr);
    }
};

} // namespace

TEST_CASE("gpu: graph culls unused passes, transitions image layouts and times passes") {
    auto& ctx = test::gpu();
    const uint32_t w = 16, h = 8;
    TestImage img(ctx, w, h);
    vk::Buffer host(ctx, w * h * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::MemoryUse::Readback);
    std::memset(host.mapped(), 0, w * h * 4);
    graph::TransientPool pool;
    graph::RenderGraph g;
    auto image = g.importImage("image", img.image, VK_IMAGE_LAYOUT_UNDEFINED);
    auto scratch = g.createBuffer("scratch", 1024, VK_BUFFER_USAGE_TRANSFER_DST_BIT);
    auto out = g.importBuffer("readback", host.handle(), host.size());
    g.addPass(
        "clear", [&](auto& b) { b.write(image, graph::Access::TransferWrite); },
        [image](VkCommandBuffer cmd, const graph::RenderGraph::Resources& r) {
            VkClearColorValue value{};
            value.uint32[0] = 0xC0FFEEu;
            VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
            vkCmdClearColorImage(cmd, r.image(image), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &value, 1,
                                 &range);
        });
    bool unusedRan = false;
    g.addPass(
        "unused", [&](auto& b) { b.write(scratch, graph::Access::TransferWrite); },
        [&unusedRan, scratch](VkCommandBuffer cmd, const graph::RenderGraph::Resources& r) {
            unusedRan = true;
            vkCmdFillBuffer(cmd, r.buffer(scratch), 0, VK_WHOLE_SIZE, 1u);
        });
    g.addPass(
        "copy",
        [&](auto& b) {
            b.read(image, graph::Access::TransferRead);
            b.write(out, graph::Access::TransferWrite);
        },
        [image, out, w, h](VkCommandBuffer cmd, const graph::RenderGraph::Resources& r) {
            VkBufferImageCopy region{};
            region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
            region.imageExtent = {w, h, 1};
            vkCmdCopyImageToBuffer(cmd, r.image(image), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, r.buffer(out),
                                   1, &region);
        });
    g.markOutput(out);
    auto timings = g.execute(ctx, pool);

    CHECK(g.livePasses() == std::vector<std::string>{"clear", "copy"});
    CHECK_FALSE(unusedRan);
    CHECK(pool.bytes() == 0); // the culled pass's transient buffer was never allocated
    CHECK(g.finalLayout(image) == VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    REQUIRE(timings.size() == 2);
    for (const auto& t : timings) CHECK(t.ms >= 0.0);
    const auto* values = static_cast<const uint32_t*>(host.mapped());
    for (uint32_t i = 0; i < w * h; ++i) REQUIRE(values[i] == 0xC0FFEEu);
    CHECK(g.graphviz().find("color=grey") != std::string::npos);
    CHECK(ctx.validationMessages() == 0);
}
