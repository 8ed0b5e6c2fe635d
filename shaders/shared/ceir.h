// Colour-enhanced isosurface rendering (paper §4): the speed-colour map lookup that colours each hit,
// and the transfer-function lookup and opacity correction of the full-volume-rendering pass it is
// compared with. Compiled as GLSL by the passes, as C++ by the host tests, and as CUDA by cuda_ref/.
//
// The includer defines, before including this file:
//   vec4 rcSpeedColourEntry(int j)  entry j (0..m) of the speed-colour map: rgb in xyz. Entry j holds the
//                                   colour for speed_j = -ln(1 - j/m) (engine/colour/speed_colour_map.hpp).
//   vec4 rcTransferEntry(int k)     entry k of the tabulated local transfer function: rgb in xyz, the
//                                   opacity for the standard sample distance s0 in w, at x = k/(entries-1).
// (CUDA includers make both __host__ __device__, as cuda_ref does for rcFetch.)
// speed = v' / densityFactor, v' being the value's derivative along the unit ray at the hit.
#ifndef ISO_CEIR_H
#define ISO_CEIR_H

#include "portable.h"

#ifndef ISO_GLSL
namespace iso::rc {
using glm::exp;
using glm::log;
using glm::mix;
#endif

// 1 - e^y for y <= 0. For small |y| the difference 1 - exp(y) would lose most of its digits in float
// (fast crossings, thin steps), so a short series takes over there; its first omitted term, y^5/120, is
// below 1e-12 for |y| < 0.01.
RC_FN float rcOneMinusExp(float y) {
    if (y > -0.01f) return -y * (1.0f + y * (0.5f + y * (1.0f / 6.0f + y * (1.0f / 24.0f))));
    return 1.0f - exp(y);
}

// ln(1 - a) for a in [0, 1). GLSL has no log1p: for small a, 1 - a would round away a's low bits, so a
// series takes over (first omitted term a^5/5 < 3e-11 for a < 0.01).
RC_FN float rcLogOneMinus(float a) {
    if (a < 0.01f) return -a * (1.0f + a * (0.5f + a * (1.0f / 3.0f + a * 0.25f)));
    return log(1.0f - a);
}

// Opacity for a step of stepOverS0 standard sample distances, from the opacity alpha for one:
// 1 - (1 - alpha)^stepOverS0. Written as 1 - e^(r ln(1 - alpha)) with the exact ends handled first, since
// pow(0, r) is undefined in GLSL and ln(0) is -infinity: alpha >= 1 stays 1 and alpha <= 0 stays 0 for
// any positive step; a zero (or negative, or NaN) step, or a NaN alpha, gives 0.
RC_FN float rcCorrectOpacity(float alpha, float stepOverS0) {
    if (!(alpha > 0.0f) || !(stepOverS0 > 0.0f)) return 0.0f;
    if (alpha >= 1.0f) return 1.0f;
    return rcOneMinusExp(stepOverS0 * rcLogOneMinus(alpha));
}

// Position u = m (1 - e^-speed) in [0, m] of speed in a map of m intervals; entry j sits at u = j.
// speed <= 0 and NaN give 0 (the surface crossed infinitely slowly shows the nearest colour). speed is
// clamped to 88 before the exponential, where e^-speed is already below float's smallest normal, so
// +infinity needs no special handling on hardware that flushes denormals.
RC_FN float rcSpeedToMapCoord(float speed, int m) {
    if (!(speed > 0.0f)) return 0.0f;
    float u = float(m) * rcOneMinusExp(-min(speed, 88.0f));
    return clamp(u, 0.0f, float(m));
}

// The material colour for a hit crossed at speed: linear between the map entries around u.
RC_FN vec3 rcSpeedColour(float speed, int m) {
    float u = rcSpeedToMapCoord(speed, m);
    int j = max(min(int(floor(u)), m - 1), 0);
    float f = u - float(j);
    return mix(vec3(rcSpeedColourEntry(j)), vec3(rcSpeedColourEntry(j + 1)), f);
}

// The transfer function at x in the section (0: the isovalue, 1: isovalue + deltaV), linear between table
// entries. Below the section (and for NaN) transparent with the colour of x = 0; above it opaque with the
// colour of x = 1.
RC_FN vec4 rcTransferAt(float x, int entries) {
    if (!(x >= 0.0f)) return vec4(vec3(rcTransferEntry(0)), 0.0f);
    if (x > 1.0f) return vec4(vec3(rcTransferEntry(entries - 1)), 1.0f);
    float u = x * float(entries - 1);
    int k = max(min(int(floor(u)), entries - 2), 0);
    float f = u - float(k);
    return mix(rcTransferEntry(k), rcTransferEntry(min(k + 1, entries - 1)), f);
}

#ifndef ISO_GLSL
} // namespace iso::rc
#endif

#endif
