// CUDA twin of shaders/comp/iso_surface.comp, from the same ray-core headers.
#include "cuda_check.hpp"
#include "cuda_renderer.hpp"

#include <cuda_runtime.h>

namespace iso::rc {
// Set per launch: the ray core's fetch hook reads the volume through this texture.
__device__ inline float rcFetchFrom(cudaTextureObject_t tex, int kind, glm::ivec3 p) {
    if (kind == 1) return float(tex3D<short>(tex, float(p.x), float(p.y), float(p.z)));
    if (kind == 2) return float(tex3D<unsigned short>(tex, float(p.x), float(p.y), float(p.z)));
    return tex3D<float>(tex, float(p.x), float(p.y), float(p.z));
}
} // namespace iso::rc

namespace {
__constant__ cudaTextureObject_t gVolume;
__constant__ int gKind;
} // namespace

namespace iso::rc {
__host__ __device__ inline float rcFetch(ivec3 p) {
#ifdef __CUDA_ARCH__
    return rcFetchFrom(gVolume, gKind, p);
#else
    (void)p;
    return 0.0f;
#endif
}
} // namespace iso::rc

#include "ray_core.h"
#include "shading.h"

namespace iso::cuda {

namespace {

__global__ void isoSurfaceKernel(rc::RenderParams params, float4* colour, float* depth, uint32_t* voxelId) {
    using namespace rc;
    uvec2 px(blockIdx.x * blockDim.x + threadIdx.x, blockIdx.y * blockDim.y + threadIdx.y);
    if (px.x >= params.image.x || px.y >= params.image.y) return;
    vec3 o, d;
    rcPrimaryRay(params, px, o, d);
    ivec3 dims = ivec3(params.dims);
    RcHit hit = rcFirstHit(o, d, vec3(params.boxMin), vec3(params.boxMax), dims, params.boxMin.w);
    uint32_t pixel = px.x + params.image.x * px.y;
    if (hit.t < 0.0f) {
        colour[pixel] = make_float4(params.background.x, params.background.y, params.background.z, 0.0f);
        depth[pixel] = -1.0f;
        voxelId[pixel] = ISO_NO_HIT_ID;
        return;
    }
    vec3 g = rcGradient(hit.pos, dims);
    vec3 c = rcShadeHeadlight(params, g, d, vec3(params.material));
    colour[pixel] = make_float4(c.x, c.y, c.z, 1.0f);
    depth[pixel] = hit.t;
    voxelId[pixel] =
        uint32_t(hit.cell.x) + params.dims.x * (uint32_t(hit.cell.y) + params.dims.y * uint32_t(hit.cell.z));
}

} // namespace

bool cudaDeviceAvailable() {
    int n = 0;
    return cudaGetDeviceCount(&n) == cudaSuccess && n > 0;
}

CudaVolume::CudaVolume(const void* data, uint32_t nx, uint32_t ny, uint32_t nz, TexelKind kind,
                       int bytesPerTexel)
    : kind_(kind) {
    cudaChannelFormatDesc desc = kind == TexelKind::Float       ? cudaCreateChannelDesc<float>()
                                 : kind == TexelKind::SignedInt ? cudaCreateChannelDesc<short>()
                                 : bytesPerTexel == 1           ? cudaCreateChannelDesc<unsigned char>()
                                                                : cudaCreateChannelDesc<unsigned short>();
    cudaArray_t array = nullptr;
    CUDA_CHECK(cudaMalloc3DArray(&array, &desc, make_cudaExtent(nx, ny, nz)));
    array_ = array;
    cudaMemcpy3DParms copy{};
    copy.srcPtr = make_cudaPitchedPtr(const_cast<void*>(data), size_t(nx) * bytesPerTexel, nx, ny);
    copy.dstArray = array;
    copy.extent = make_cudaExtent(nx, ny, nz);
    copy.kind = cudaMemcpyHostToDevice;
    CUDA_CHECK(cudaMemcpy3D(&copy));
    cudaResourceDesc res{};
    res.resType = cudaResourceTypeArray;
    res.res.array.array = array;
    cudaTextureDesc tex{};
    tex.addressMode[0] = tex.addressMode[1] = tex.addressMode[2] = cudaAddressModeClamp;
    tex.filterMode = cudaFilterModePoint;
    tex.readMode = cudaReadModeElementType;
    tex.normalizedCoords = 0;
    cudaTextureObject_t object = 0;
    CUDA_CHECK(cudaCreateTextureObject(&object, &res, &tex, nullptr));
    texture_ = object;
}

CudaVolume::~CudaVolume() {
    if (texture_) cudaDestroyTextureObject(cudaTextureObject_t(texture_));
    if (array_) cudaFreeArray(static_cast<cudaArray_t>(array_));
}

CudaFrame renderIsoSurface(const CudaVolume& volume, const rc::RenderParams& params) {
    const size_t pixels = size_t(params.image.x) * params.image.y;
    cudaTextureObject_t tex = volume.texture();
    int kind = volume.kind() == TexelKind::Float ? 0 : volume.kind() == TexelKind::SignedInt ? 1 : 2;
    CUDA_CHECK(cudaMemcpyToSymbol(gVolume, &tex, sizeof tex));
    CUDA_CHECK(cudaMemcpyToSymbol(gKind, &kind, sizeof kind));
    float4* colour = nullptr;
    float* depth = nullptr;
    uint32_t* ids = nullptr;
    CUDA_CHECK(cudaMalloc(&colour, pixels * sizeof(float4)));
    CUDA_CHECK(cudaMalloc(&depth, pixels * sizeof(float)));
    CUDA_CHECK(cudaMalloc(&ids, pixels * sizeof(uint32_t)));
    cudaEvent_t start, stop;
    CUDA_CHECK(cudaEventCreate(&start));
    CUDA_CHECK(cudaEventCreate(&stop));
    dim3 block(ISO_WORKGROUP_X, ISO_WORKGROUP_Y);
    dim3 grid((params.image.x + block.x - 1) / block.x, (params.image.y + block.y - 1) / block.y);
    CUDA_CHECK(cudaEventRecord(start));
    isoSurfaceKernel<<<grid, block>>>(params, colour, depth, ids);
    CUDA_CHECK(cudaGetLastError());
    CUDA_CHECK(cudaEventRecord(stop));
    CUDA_CHECK(cudaEventSynchronize(stop));
    CudaFrame frame;
    CUDA_CHECK(cudaEventElapsedTime(&frame.kernelMs, start, stop));
    frame.rgba.resize(pixels * 4);
    frame.depth.resize(pixels);
    frame.voxelIds.resize(pixels);
    CUDA_CHECK(cudaMemcpy(frame.rgba.data(), colour, pixels * sizeof(float4), cudaMemcpyDeviceToHost));
    CUDA_CHECK(cudaMemcpy(frame.depth.data(), depth, pixels * sizeof(float), cudaMemcpyDeviceToHost));
    CUDA_CHECK(cudaMemcpy(frame.voxelIds.data(), ids, pixels * sizeof(uint32_t), cudaMemcpyDeviceToHost));
    CUDA_CHECK(cudaEventDestroy(start));
    CUDA_CHECK(cudaEventDestroy(stop));
    CUDA_CHECK(cudaFree(colour));
    CUDA_CHECK(cudaFree(depth));
    CUDA_CHECK(cudaFree(ids));
    return frame;
}

} // namespace iso::cuda
