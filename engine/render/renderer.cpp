#include "render/renderer.hpp"

#include "iso_params.h"
#include "vk/check.hpp"

#include "iso_surface_float.spv.h"
#include "iso_surface_sint.spv.h"
#include "iso_surface_uint.spv.h"
#include "full_volume_float.spv.h"
#include "full_volume_sint.spv.h"
#include "full_volume_uint.spv.h"

#include <glm/gtc/matrix_inverse.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace iso {

static_assert(sizeof(rc::RenderParams) == 19 * 16, "RenderParams must match its std140 block");
static_assert(offsetof(rc::RenderParams, boxMin) == 7 * 16, "RenderParams member order must match GLSL");
static_assert(offsetof(rc::RenderParams, background) == 13 * 16, "RenderParams member order must match GLSL");
static_assert(offsetof(rc::RenderParams, counts) == 16 * 16, "RenderParams member order must match GLSL");
static_assert(offsetof(rc::RenderParams, seedColours) == 17 * 16,
              "std140 arrays of vec4 have a 16-byte stride");

namespace {

VkFormat texelFormat(VoxelType t) {
    switch (t) {
    case VoxelType::U8:
        return VK_FORMAT_R8_UINT;
    case VoxelType::I16:
        return VK_FORMAT_R16_SINT;
    case VoxelType::U16:
        return VK_FORMAT_R16_UINT;
    case VoxelType::F32:
        return VK_FORMAT_R32_SFLOAT;
    }
    throw std::logic_error("unknown voxel type");
}

int volumeKind(VoxelType t) {
    switch (t) {
    case VoxelType::F32:
        return 0;
    case VoxelType::I16:
        return 1;
    default:
        return 2;
    }
}

constexpr uint32_t kTransferEntries = 1024; // tabulated transfer function for the FVR pass

glm::vec4 v4(const glm::dvec3& v, double w = 0.0) {
    return glm::vec4(glm::dvec4(v, w));
}

// The camera mapped into index space, plus the crop box and shading (see RenderParams).
rc::RenderParams makeParams(const Volume& vol, const RenderSettings& s) {
    const Camera& cam = s.camera;
    // world = origin + M * index, with M = directions * diag(spacing)
    glm::dmat3 M =
        vol.directions * glm::dmat3(glm::dvec3(vol.spacing.x, 0, 0), glm::dvec3(0, vol.spacing.y, 0),
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
    p.background = glm::vec4(s.shading.background, s.shade ? 1.0f : 0.0f);
    const double minSpacing = std::min({vol.spacing.x, vol.spacing.y, vol.spacing.z});
    const double density = s.densityFactor.value_or(defaultDensityFactor(s.tf.deltaV, minSpacing));
    p.ceir = glm::vec4(float(density), float(s.tf.deltaV), float(0.25 * minSpacing),
                       float(s.deepReach.value_or(16.0 * minSpacing)));
    p.fvr = glm::vec4(float(s.fvrStep.value_or(0.25 * minSpacing)), float(s.tf.deltaV / density), 0.0f, 0.0f);
    p.counts = glm::uvec4(uint32_t(s.mapIntervals), kTransferEntries, 0, 0);
    p.seedColours[0] = glm::vec4(s.foregroundColour, 1.0f);
    p.seedColours[1] = glm::vec4(s.backgroundColour, 1.0f);
    return p;
}

template <typename T>
std::vector<T> copyOut(const vk::Buffer& b, size_t count) {
    std::vector<T> out(count);
    std::memcpy(out.data(), b.mapped(), count * sizeof(T));
    return out;
}

} // namespace

const char* modeName(RenderMode m) {
    switch (m) {
    case RenderMode::Mono:
        return "mono";
    case RenderMode::CeirShallow:
        return "ceir-shallow";
    case RenderMode::CeirDeep:
        return "ceir-deep";
    case RenderMode::Fvr:
        return "fvr";
    }
    return "?";
}

std::optional<RenderMode> parseMode(const std::string& s) {
    for (RenderMode m : {RenderMode::Mono, RenderMode::CeirShallow, RenderMode::CeirDeep, RenderMode::Fvr})
        if (s == modeName(m)) return m;
    return std::nullopt;
}

void addPeelWindow(std::vector<uint32_t>& peelBuffer, int width, int height, int x0, int y0, int x1, int y1) {
    peelBuffer.resize(size_t(width) * size_t(height), 0u);
    for (int y = std::max(y0, 0); y < std::min(y1, height); ++y)
        for (int x = std::max(x0, 0); x < std::min(x1, width); ++x)
            ++peelBuffer[size_t(y) * size_t(width) + size_t(x)];
}

double Frame::gpuMs(const std::string& pass) const {
    for (const auto& t : timings)
        if (t.name == pass) return t.ms;
    return 0.0;
}

Renderer::Renderer(const vk::Context& ctx)
    : ctx_(ctx),
      params_(ctx, sizeof(rc::RenderParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, vk::MemoryUse::Upload) {}

void Renderer::setVolume(const Volume& vol) {
    if (vol.dims[0] < 2 || vol.dims[1] < 2 || vol.dims[2] < 2)
        throw std::runtime_error(vol.source +
                                 ": a volume needs at least 2 samples along every axis to hold cells");
    if (vol.sampleCount() >= (std::size_t(1) << 32))
        throw std::runtime_error(vol.source + ": " + std::to_string(vol.sampleCount()) +
                                 " samples: voxel ids are 32-bit, so scans of 2^32 samples or more are not "
                                 "supported yet (crop or resample the scan)");
    volumeImage_ =
        vk::VolumeImage(ctx_, texelFormat(vol.type), vol.dims[0], vol.dims[1], vol.dims[2], vol.data);
    geometry_ = vol;
    geometry_.data.clear();
    geometry_.data.shrink_to_fit();
    volumeKind_ = volumeKind(vol.type);
    hasVolume_ = true;
}

std::vector<VkDescriptorType> passBindings() {
    std::vector<VkDescriptorType> bindings(9, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    bindings[ISO_BINDING_PARAMS] = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    bindings[ISO_BINDING_VOLUME] = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    return bindings;
}

vk::ComputePipeline& Renderer::isoPipeline(RenderMode mode, bool peel, bool seeds) {
    std::array<int, 4> key{volumeKind_, int(mode), peel, seeds};
    auto it = isoPipelines_.find(key);
    if (it != isoPipelines_.end()) return it->second;
    std::span<const uint32_t> code = volumeKind_ == 0   ? std::span<const uint32_t>(iso_surface_float_spv)
                                     : volumeKind_ == 1 ? std::span<const uint32_t>(iso_surface_sint_spv)
                                                        : std::span<const uint32_t>(iso_surface_uint_spv);
    int shaderMode = mode == RenderMode::CeirShallow ? ISO_MODE_CEIR_SHALLOW
                     : mode == RenderMode::CeirDeep  ? ISO_MODE_CEIR_DEEP
                                                     : ISO_MODE_MONO;
    std::vector<vk::SpecConstant> constants{{ISO_SPEC_MODE, uint32_t(shaderMode)},
                                            {ISO_SPEC_PEEL, peel ? 1u : 0u},
                                            {ISO_SPEC_SEEDS, seeds ? 1u : 0u}};
    return isoPipelines_.emplace(key, vk::ComputePipeline(ctx_, code, passBindings(), constants))
        .first->second;
}

vk::ComputePipeline& Renderer::fvrPipeline() {
    auto it = fvrPipelines_.find(volumeKind_);
    if (it != fvrPipelines_.end()) return it->second;
    std::span<const uint32_t> code = volumeKind_ == 0   ? std::span<const uint32_t>(full_volume_float_spv)
                                     : volumeKind_ == 1 ? std::span<const uint32_t>(full_volume_sint_spv)
                                                        : std::span<const uint32_t>(full_volume_uint_spv);
    return fvrPipelines_.emplace(volumeKind_, vk::ComputePipeline(ctx_, code, passBindings())).first->second;
}

vk::Buffer& Renderer::readback(const std::string& name, VkDeviceSize size) {
    auto& b = readbacks_[name];
    if (b.size() != size)
        b = vk::Buffer(ctx_, size, VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::MemoryUse::Readback);
    return b;
}

Frame Renderer::render(const RenderSettings& s, const FrameOutputs& outputs) {
    if (!hasVolume_) throw std::logic_error("Renderer::render before setVolume");
    if (s.width <= 0 || s.height <= 0) throw std::invalid_argument("image size must be positive");
    const VkDeviceSize pixels = VkDeviceSize(s.width) * VkDeviceSize(s.height);
    if (!s.peelBuffer.empty() && s.peelBuffer.size() != pixels)
        throw std::invalid_argument("the peel buffer must hold one count per pixel");
    rc::RenderParams params = makeParams(geometry_, s);

    // Only what this scene uses is built and bound; unused bindings see one tiny buffer.
    const bool ceir = s.mode == RenderMode::CeirShallow || s.mode == RenderMode::CeirDeep;
    const bool fvr = s.mode == RenderMode::Fvr;
    const bool peel = !s.peelBuffer.empty() && !fvr;
    const bool seeds = (!s.foregroundSeeds.empty() || !s.backgroundSeeds.empty()) && !fvr;
    const VkBufferUsageFlags read = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    if (!unused_) unused_ = vk::Buffer::deviceLocalCopy(ctx_, nullptr, 16, read);
    if (ceir) {
        const SpeedColourMap& map = mapCache_.get(s.tf, s.mapIntervals);
        if (mapCache_.rebuiltLastCall() || !speedColourMap_)
            speedColourMap_ = vk::Buffer::deviceLocalCopy(ctx_, map.entries.data(),
                                                          map.entries.size() * sizeof(glm::vec4), read);
    }
    if (fvr && (!transferTable_ || !(tableOf_ == s.tf))) {
        auto table = tabulate(s.tf, int(kTransferEntries));
        transferTable_ =
            vk::Buffer::deviceLocalCopy(ctx_, table.data(), table.size() * sizeof(glm::vec4), read);
        tableOf_ = s.tf;
    }
    if (peel) peelBuffer_ = vk::Buffer::deviceLocalCopy(ctx_, s.peelBuffer.data(), pixels * 4, read);
    if (seeds) {
        std::vector<uint32_t> fg = s.foregroundSeeds, bg = s.backgroundSeeds;
        std::sort(fg.begin(), fg.end());
        std::sort(bg.begin(), bg.end());
        fg.erase(std::unique(fg.begin(), fg.end()), fg.end());
        bg.erase(std::unique(bg.begin(), bg.end()), bg.end());
        params.counts.z = uint32_t(fg.size());
        params.counts.w = uint32_t(bg.size());
        fg.insert(fg.end(), bg.begin(), bg.end());
        seeds_ = vk::Buffer::deviceLocalCopy(ctx_, fg.data(), fg.size() * 4, read);
    }
    std::memcpy(params_.mapped(), &params, sizeof params);

    const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    graph::RenderGraph g;
    auto paramsId = g.importBuffer("params", params_.handle(), params_.size());
    auto colour = g.createBuffer("colour", pixels * 16, storage);
    auto depth = g.createBuffer("depth", pixels * 4, storage);
    auto voxelIds = g.createBuffer("voxelIdBuffer", pixels * 4, storage);
    std::optional<graph::ResourceId> mapId, tableId, peelId, seedsId;
    if (ceir) mapId = g.importBuffer("speedColourMap", speedColourMap_.handle(), speedColourMap_.size());
    if (fvr) tableId = g.importBuffer("transferTable", transferTable_.handle(), transferTable_.size());
    if (peel) peelId = g.importBuffer("peelBuffer", peelBuffer_.handle(), peelBuffer_.size());
    if (seeds) seedsId = g.importBuffer("seedLists", seeds_.handle(), seeds_.size());

    vk::ComputePipeline& pipeline = fvr ? fvrPipeline() : isoPipeline(s.mode, peel, seeds);
    VkImageView view = volumeImage_.view();
    VkSampler sampler = volumeImage_.sampler();
    VkBuffer unused = unused_.handle();
    g.addPass(
        fvr ? "fullVolume" : "isoSurface",
        [&](graph::RenderGraph::PassBuilder& b) {
            b.read(paramsId, graph::Access::UniformRead);
            for (auto id : {mapId, tableId, peelId, seedsId})
                if (id) b.read(*id);
            b.write(colour);
            b.write(depth);
            b.write(voxelIds);
        },
        [&pipeline, paramsId, colour, depth, voxelIds, mapId, tableId, peelId, seedsId, view, sampler, unused,
         s](VkCommandBuffer cmd, const graph::RenderGraph::Resources& r) {
            auto orUnused = [&](std::optional<graph::ResourceId> id) { return id ? r.buffer(*id) : unused; };
            pipeline.bindBuffer(ISO_BINDING_PARAMS, r.buffer(paramsId));
            pipeline.bindImage(ISO_BINDING_VOLUME, view, sampler);
            pipeline.bindBuffer(ISO_BINDING_COLOUR, r.buffer(colour));
            pipeline.bindBuffer(ISO_BINDING_DEPTH, r.buffer(depth));
            pipeline.bindBuffer(ISO_BINDING_VOXEL_ID, r.buffer(voxelIds));
            pipeline.bindBuffer(ISO_BINDING_SPEED_COLOUR_MAP, orUnused(mapId));
            pipeline.bindBuffer(ISO_BINDING_TRANSFER_TABLE, orUnused(tableId));
            pipeline.bindBuffer(ISO_BINDING_PEEL_BUFFER, orUnused(peelId));
            pipeline.bindBuffer(ISO_BINDING_SEEDS, orUnused(seedsId));
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
        if (i % 4 != 3)
            v = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
        else
            v = 1.0f; // files show the background too, so they are opaque
        out[i] = uint8_t(std::lround(v * 255.0f));
    }
    return out;
}

} // namespace iso
