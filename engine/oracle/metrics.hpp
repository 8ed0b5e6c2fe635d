// How far a GPU image is from the oracle's: hit/miss agreement, depth error, cell ids, normals.
#pragma once

#include "io/volume.hpp"
#include "oracle/oracle.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <string>

namespace iso::oracle {

struct Metrics {
    double hitMissMismatch = 0.0;                          // fraction of all pixels
    double depthP50 = 0.0, depthP99 = 0.0, depthMax = 0.0; // voxel units: |t - tref| / min(spacing)
    double idMismatch = 0.0;                               // fraction of pixels both hit; NaN if no ids given
    double normalP99Deg = 0.0;                             // NaN if no normals given
    uint64_t nonFinite = 0; // pixels with a NaN/inf depth, or normal where both hit
    uint64_t pixels = 0, bothHit = 0;
    int worstX = -1, worstY = -1; // pixel of depthMax; -1 when no pixel was compared
};

// depth: per pixel world distance t along the primary ray, -1 (any negative) = miss; a non-finite
// depth counts as a hit whose depth is unusable (it is counted in nonFinite, not in the depth stats).
// ids: cell ids, 0xFFFFFFFF or UINT64_MAX = none (a mismatch where the oracle hit); empty = not given.
// normals: unit normals, empty = not given. They are compared with the oracle's -gradient/|gradient|,
// which points out of the f >= iso region.
// Percentiles are nearest-rank; with no pixels to compare a statistic is 0. Sizes must be
// ref.width*ref.height (std::invalid_argument otherwise).
Metrics compare(const Image& ref, const Volume& vol, std::span<const float> depth,
                std::span<const uint64_t> ids, std::span<const glm::vec3> normals = {});

// One line, for logs and test failure messages.
std::string format(const Metrics& m);

} // namespace iso::oracle
