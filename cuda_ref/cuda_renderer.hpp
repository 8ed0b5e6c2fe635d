// The CUDA reference renderer: the same scene in, the same buffers out as the Vulkan isoSurface pass.
#pragma once

#include "iso_params.h"

#include <cstdint>
#include <vector>

namespace iso::cuda {

enum class TexelKind { Float, SignedInt, UnsignedInt };

struct CudaFrame {
    std::vector<float> rgba;
    std::vector<float> depth;
    std::vector<uint32_t> voxelIds;
    float kernelMs = 0.0f;
};

// Uploads a volume (x fastest) as a 3D array sampled by texel fetches, like the Vulkan path.
class CudaVolume {
  public:
    CudaVolume(const void* data, uint32_t nx, uint32_t ny, uint32_t nz, TexelKind kind, int bytesPerTexel);
    ~CudaVolume();
    CudaVolume(const CudaVolume&) = delete;
    CudaVolume& operator=(const CudaVolume&) = delete;
    unsigned long long texture() const { return texture_; }
    TexelKind kind() const { return kind_; }

  private:
    void* array_ = nullptr;
    unsigned long long texture_ = 0;
    TexelKind kind_;
};

bool cudaDeviceAvailable();
CudaFrame renderIsoSurface(const CudaVolume& volume, const rc::RenderParams& params);

} // namespace iso::cuda
