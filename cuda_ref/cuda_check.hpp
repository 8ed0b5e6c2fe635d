// Every CUDA call goes through CUDA_CHECK: a failure throws with the call's text, the error's
// name and the place, in every build type.
#pragma once

#include <cuda_runtime.h>

#include <stdexcept>
#include <string>

namespace iso::cuda {

struct CudaError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

[[noreturn]] inline void throwCudaError(cudaError_t e, const char* call, const char* file, int line) {
    throw CudaError(std::string("CUDA call failed with ") + cudaGetErrorName(e) + " (" +
                    cudaGetErrorString(e) + "): " + call + " (" + file + ":" + std::to_string(line) + ")");
}

} // namespace iso::cuda

#define CUDA_CHECK(call)                                                                                     \
    do {                                                                                                     \
        cudaError_t cudaCheckResult_ = (call);                                                               \
        if (cudaCheckResult_ != cudaSuccess)                                                                 \
            ::iso::cuda::throwCudaError(cudaCheckResult_, #call, __FILE__, __LINE__);                        \
    } while (0)
