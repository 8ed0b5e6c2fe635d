// Turns a scene (volume + view + isovalue) into a frame: builds the render graph with only the
// passes the requested outputs need, runs it, and reads the results back.
#pragma once

#include "colour/speed_colour_map.hpp"
#include "colour/transfer_function.hpp"
#include "graph/render_graph.hpp"
#include "io/volume.hpp"
#include "scene/camera.hpp"
#include "vk/resources.hpp"

#include <array>
#include <map>
#include <optional>
#include <vector>

namespace iso {

struct Shading {
    glm::vec3 material{0.90f, 0.82f, 0.70f}; // linear RGB
    float ambient = 0.12f;
    float diffuse = 0.80f;
    float specular = 0.20f;
    float shininess = 40.0f;
    glm::vec3 background{0.012f, 0.014f, 0.020f}; // linear RGB
};

enum class RenderMode { Mono, CeirShallow, CeirDeep, Fvr };
const char* modeName(RenderMode m); // "mono", "ceir-shallow", "ceir-deep", "fvr"
std::optional<RenderMode> parseMode(const std::string& s);

struct RenderSettings {
    int width = 512;
    int height = 512;
    Camera camera;
    double iso = 0.0;                          // in the scan's own units
    std::optional<std::array<double, 6>> crop; // i0,j0,k0,i1,j1,k1 in sample-index units
    Shading shading;
    bool shade = true; // false: the material colour alone (no lighting)

    RenderMode mode = RenderMode::Mono;
    LocalTransferFunction tf = defaultTransferFunction(); // CEIR and FVR
    std::optional<double> densityFactor;                  // default: tf.deltaV / smallest spacing
    int mapIntervals = 256;                               // m of the speed-colour map
    std::optional<double> deepReach; // world units; default 16 smallest spacings, at most 256 voxels
    std::optional<double> fvrStep;   // world units; default a quarter of the smallest spacing

    // Surface peeling (paper §5.2): crossings to skip, one count per pixel; empty for none.
    std::vector<uint32_t> peelBuffer;
    // Seed preview colouring (paper §5.4): voxel ids, any order; empty for none.
    std::vector<uint32_t> foregroundSeeds, backgroundSeeds;
    glm::vec3 foregroundColour{0.10f, 0.75f, 0.20f};
    glm::vec3 backgroundColour{0.85f, 0.15f, 0.15f};
};

// Adds 1 to the peel count of the pixels in [x0,x1) x [y0,y1) (clipped to the image).
void addPeelWindow(std::vector<uint32_t>& peelBuffer, int width, int height, int x0, int y0, int x1, int y1);

// What the caller wants back; the graph keeps only the passes these need.
struct FrameOutputs {
    bool colour = true;
    bool depth = false;
    bool voxelIds = false;
};

struct Frame {
    int width = 0, height = 0;
    std::vector<float> rgba;        // linear RGBA, row 0 at the top
    std::vector<float> depth;       // distance along the unit ray, -1 where nothing is hit
    std::vector<uint32_t> voxelIds; // i + nx*(j + ny*k) of the hit cell, 0xFFFFFFFF where nothing is hit
    std::vector<graph::PassTiming> timings;
    double gpuMs(const std::string& pass) const; // one pass's GPU time, 0 if it did not run
};

class Renderer {
  public:
    explicit Renderer(const vk::Context& ctx);

    // Uploads the scan once; later frames only change parameters.
    void setVolume(const Volume& vol);
    Frame render(const RenderSettings& settings, const FrameOutputs& outputs = {});

    const vk::Context& context() const { return ctx_; }
    VkDeviceSize volumeBytes() const { return volumeImage_.memoryBytes(); }
    VkDeviceSize frameBytes() const { return transients_.bytes(); }

  private:
    const vk::Context& ctx_;
    Volume geometry_; // the scan without its samples: dims, spacing, origin, directions
    bool hasVolume_ = false;
    int volumeKind_ = 0; // 0 float, 1 signed integer, 2 unsigned integer texels
    vk::VolumeImage volumeImage_;
    vk::Buffer params_;
    std::map<std::array<int, 4>, vk::ComputePipeline> isoPipelines_;
    std::map<std::string, vk::Buffer> readbacks_;
    graph::TransientPool transients_;

    // Data the passes read every frame but which change rarely: rebuilt only when their inputs do.
    SpeedColourMapCache mapCache_;
    vk::Buffer speedColourMap_;
    LocalTransferFunction tableOf_;
    vk::Buffer transferTable_;
    vk::Buffer peelBuffer_, seeds_, unused_;
    std::map<int, vk::ComputePipeline> fvrPipelines_;

    vk::ComputePipeline& isoPipeline(RenderMode mode, bool peel, bool seeds);
    vk::ComputePipeline& fvrPipeline();
    vk::Buffer& readback(const std::string& name, VkDeviceSize size);
};

// Linear RGBA floats to 8-bit sRGB-encoded RGBA for display files.
std::vector<uint8_t> encodeSrgb8(const std::vector<float>& rgba);

} // namespace iso
