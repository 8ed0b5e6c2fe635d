#include "render/renderer.hpp"

#include "iso_params.h"
#include "vk/check.hpp"

#include "iso_surface_float.spv.h"
#include "iso_surface_sint.spv.h"
#include "iso_surface_uint.spv.h"

#include <glm/gtc/matrix_inverse.hpp>

#include <cmath>
#include <cstring>
#include <stdexcept>

namespace iso {

static_assert(sizeof(rc::RenderParams) == 14 * 16, "RenderParams must match its std140 block");
static_assert(offsetof(rc::RenderParams, boxMin) == 7 * 16, "RenderParams member order must match GLSL");
static_assert(offsetof(rc::RenderParams, background) == 13 * 16, "RenderParams member order must match GLSL");

namespace {

VkFormat texelFormat(VoxelType t) {
    switch (t) {
    case VoxelType::U8: return VK_FORMAT_R8_UINT;
    case VoxelType::I16: return VK_FORMAT_R16_SINT;
    case VoxelType::U16: return VK_FORMAT_R16_UINT;
    case VoxelType::F32: return VK_FORMAT_R32_SFLOAT;
    }
    throw std::logic_error("unknown voxel type");
}

int volumeKind(VoxelType t) {
    switch (t) {
    case VoxelType::F32: return 0;
    case VoxelType::I16: return 1;
    default: return 2;
    }
}

glm::vec4 v4(const glm::dvec3& v, double w = 0.0) { return glm::vec4(glm::dvec4(v, w)); }

// The camera mapped into index space, plus the crop box and shading (see RenderParams).
rc::RenderParams makeParams(const Volume& vol, const RenderSettings& s) {
    const Camera& cam = s.camera;
    // world = origin + M * index, with M = directions * diag(spacing)
    glm::dmat3 M = vol.directions * glm::dmat3(glm::dvec3(vol.spacing.x, 0, 0), glm::dvec3(0, vol.spacing.y, 0),
                                               glm::dvec3(0, 0, vol.spacing.z));
    glm::dmat3 toIndex = glm::inverse(M);
    glm::dvec3 forward = glm::normalize(cam.target - cam.eye);
    glm::dvec3 right = glm::normalize(glm::cross(forward, cam.up));
    glm::dvec3 up = glm::cross(right, forward);
    double aspect = double(s.width) / double(s.height);
    double halfV = cam.orthographic ? 0.5 * cam.height : std::tan(glm::radians(cam.fovyDeg) * 0.5);

    rc::RenderParams p{};
    p.eye = v4(toIndex * (cam.eye - vol.origin), cam.orthographic ? 1.0 : 0.0);
    p.forward = v4(toIndex * forward, halfV * aspect);
    p.right = v4(toIndex * right, halfV);
    p.up = v4(toIndex * up);
    glm::dmat3 rows = glm::transpose(toIndex); // columns of the transpose are the rows
    p.toIndex0 = v4(rows[0]);
    p.toIndex1 = v4(rows[1]);
    p.toIndex2 = v4(rows[2]);
    glm::dvec3 hi(vol.dims[0] - 1.0, vol.dims[1] - 1.0, vol.dims[2] - 1.0);
    glm::dvec3 bmin(0.0), bmax = hi;
    if (s.crop) {
        const auto& c = *s.crop;
        bmin = glm::clamp(glm::dvec3(c[0], c[1], c[2]), glm::dvec3(0.0), hi);
        bmax = glm::clamp(glm::dvec3(c[3], c[4], c[5]), glm::dvec3(0.0), hi);
    }
    p.boxMin = v4(bmin, s.iso);
    p.boxMax = v4(bmax, 0.0);
    p.dims = glm::uvec4(vol.dims[0], vol.dims[1], vol.dims[2], 0);
    p.image = glm::uvec4(uint32_t(s.width), uint32_t(s.height), 0, 0);
    p.material = glm::vec4(s.shading.material, s.shading.ambient);
    p.lighting = glm::vec4(s.shading.diffuse, s.shading.specular, s.shading.shininess, 0.0f);
    p.background = glm::vec4(s.shading.background, 0.0f);
    return p;
}

template <typename T>
std::vector<T> copyOut(const vk::Buffer& b, size_t count) {
    std::vector<T> out(count);
    std::memcpy(out.data(), b.mapped(), count * sizeof(T));
    return out;
}

} // namespace

double Frame::gpuMs(const std::string& pass) const {
    for (const auto& t : timings)
        if (t.name == pass) return t.ms;
    return 0.0;
}

Renderer::Renderer(const vk::Context& ctx)
    : ctx_(ctx), params_(ctx, sizeof(rc::RenderParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, vk::MemoryUse::Upload) {}

void Renderer::setVolume(const Volume& vol) {
    if (vol.dims[0] < 2 || vol.dims[1] < 2 || vol.dims[2] < 2)
        throw std::runtime_error(vol.source + ": a volume needs at least 2 samples along every axis to hold cells");
    volumeImage_ = vk::VolumeImage(ctx_, texelFormat(vol.type), vol.dims[0], vol.dims[1], vol.dims[2], vol.data);
    geometry_ = vol;
    geometry_.data.clear();
    geometry_.data.shrink_to_fit();
    volumeKind_ = volumeKind(vol.type);
    hasVolume_ = true;
}

vk::ComputePipeline& Renderer::isoPipeline() {
    auto it = isoPipelines_.find(volumeKind_);
    if (it != isoPipelines_.end()) return it->second;
    std::span<const uint32_t> code = volumeKind_ == 0   ? std::span<const uint32_t>(iso_surface_float_spv)
                                     : volumeKind_ == 1 ? std::span<const uint32_t>(iso_surface_sint_spv)
                                                        : std::span<const uint32_t>(iso_surface_uint_spv);
    std::vector<VkDescriptorType> bindings(5);
    bindings[ISO_BINDING_PARAMS] = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    bindings[ISO_BINDING_VOLUME] = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    bindings[ISO_BINDING_COLOUR] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    bindings[ISO_BINDING_DEPTH] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    bindings[ISO_BINDING_VOXEL_ID] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    return isoPipelines_.emplace(volumeKind_, vk::ComputePipeline(ctx_, code, bindings)).first->second;
}

vk::Buffer& Renderer::readback(const std::string& name, VkDeviceSize size) {
    auto& b = readbacks_[name];
    if (b.size() != size) b = vk::Buffer(ctx_, size, VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::MemoryUse::Readback);
    return b;
}

Frame Renderer::render(const RenderSettings& s, const FrameOutputs& outputs) {
    if (!hasVolume_) throw std::logic_error("Renderer::render before setVolume");
    if (s.width <= 0 || s.height <= 0) throw std::invalid_argument("image size must be positive");
    const rc::RenderParams params = makeParams(geometry_, s);
    std::memcpy(params_.mapped(), &params, sizeof params);

    const VkDeviceSize pixels = VkDeviceSize(s.width) * VkDeviceSize(s.height);
    const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    graph::RenderGraph g;
    auto paramsId = g.importBuffer("params", params_.handle(), params_.size());
    auto colour = g.createBuffer("colour", pixels * 16, storage);
    auto depth = g.createBuffer("depth", pixels * 4, storage);
    auto voxelIds = g.createBuffer("voxelIdBuffer", pixels * 4, storage);
    vk::ComputePipeline& pipeline = isoPipeline();
    VkImageView view = volumeImage_.view();
    VkSampler sampler = volumeImage_.sampler();
    g.addPass(
        "isoSurface",
        [&](graph::RenderGraph::PassBuilder& b) {
            b.read(paramsId, graph::Access::UniformRead);
            b.write(colour);
            b.write(depth);
            b.write(voxelIds);
        },
        [&pipeline, paramsId, colour, depth, voxelIds, view, sampler, s](VkCommandBuffer cmd,
                                                                          const graph::RenderGraph::Resources& r) {
            pipeline.bindBuffer(ISO_BINDING_PARAMS, r.buffer(paramsId));
            pipeline.bindImage(ISO_BINDING_VOLUME, view, sampler);
            pipeline.bindBuffer(ISO_BINDING_COLOUR, r.buffer(colour));
            pipeline.bindBuffer(ISO_BINDING_DEPTH, r.buffer(depth));
            pipeline.bindBuffer(ISO_BINDING_VOXEL_ID, r.buffer(voxelIds));
            pipeline.dispatch(cmd, (uint32_t(s.width) + ISO_WORKGROUP_X - 1) / ISO_WORKGROUP_X,
                              (uint32_t(s.height) + ISO_WORKGROUP_Y - 1) / ISO_WORKGROUP_Y, 1);
        });

    struct Wanted {
        bool on;
        graph::ResourceId src;
        const char* name;
        VkDeviceSize bytes;
    };
    const Wanted wanted[] = {{outputs.colour, colour, "colourReadback", pixels * 16},
                             {outputs.depth, depth, "depthReadback", pixels * 4},
                             {outputs.voxelIds, voxelIds, "voxelIdReadback", pixels * 4}};
    std::vector<std::pair<const Wanted*, vk::Buffer*>> copies;
    for (const auto& w : wanted) {
        if (!w.on) continue;
        vk::Buffer& host = readback(w.name, w.bytes);
        auto dst = g.importBuffer(w.name, host.handle(), host.size());
        g.addPass(
            std::string("readback:") + w.name,
            [&](graph::RenderGraph::PassBuilder& b) {
                b.read(w.src, graph::Access::TransferRead);
                b.write(dst, graph::Access::TransferWrite);
            },
            [src = w.src, dst, bytes = w.bytes](VkCommandBuffer cmd, const graph::RenderGraph::Resources& r) {
                VkBufferCopy region{0, 0, bytes};
                vkCmdCopyBuffer(cmd, r.buffer(src), r.buffer(dst), 1, &region);
            });
        g.markOutput(dst);
        copies.push_back({&w, &host});
    }

    Frame frame;
    frame.width = s.width;
    frame.height = s.height;
    frame.timings = g.execute(ctx_, transients_);
    for (auto [w, host] : copies) {
        if (w->src == colour) frame.rgba = copyOut<float>(*host, size_t(pixels) * 4);
        if (w->src == depth) frame.depth = copyOut<float>(*host, size_t(pixels));
        if (w->src == voxelIds) frame.voxelIds = copyOut<uint32_t>(*host, size_t(pixels));
    }
    return frame;
}

std::vector<uint8_t> encodeSrgb8(const std::vector<float>& rgba) {
    std::vector<uint8_t> out(rgba.size());
    for (size_t i = 0; i < rgba.size(); ++i) {
        float v = std::isfinite(rgba[i]) ? std::fmin(std::fmax(rgba[i], 0.0f), 1.0f) : 0.0f;
        if (i % 4 != 3) v = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
        else v = 1.0f; // files show the background too, so they are opaque
        out[i] = uint8_t(std::lround(v * 255.0f));
    }
    return out;
}

} // namespace iso
