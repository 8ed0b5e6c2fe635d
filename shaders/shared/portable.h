// Lets one header compile as GLSL, as C++ (with GLM) and as CUDA, so the ray core exists once.
// GLSL includers define ISO_GLSL before including; C++ and CUDA get GLM's GLSL-like types.
#ifndef ISO_PORTABLE_H
#define ISO_PORTABLE_H

#ifdef ISO_GLSL
#define RC_FN
#define RC_INOUT(T) inout T
#define RC_OUT(T) out T
#define RC_OUT_ARRAY(T) out T
#define RC_CONST const
#else
#include <glm/glm.hpp>
#include <cstdint>
#ifdef __CUDACC__
#define RC_FN __host__ __device__ inline
#else
#define RC_FN inline
#endif
#define RC_INOUT(T) T&
#define RC_OUT(T) T&
#define RC_OUT_ARRAY(T) T // arrays decay to pointers, so writes reach the caller
#define RC_CONST const
namespace iso::rc {
using glm::ivec3;
using glm::uvec2;
using glm::uvec3;
using glm::uvec4;
using glm::vec2;
using glm::vec3;
using glm::vec4;
using uint = uint32_t;
using glm::abs;
using glm::any;
using glm::ceil;
using glm::clamp;
using glm::dot;
using glm::floor;
using glm::greaterThan;
using glm::isinf;
using glm::isnan;
using glm::lessThan;
using glm::max;
using glm::min;
using glm::normalize;
using glm::sqrt;
} // namespace iso::rc
#endif

#endif
