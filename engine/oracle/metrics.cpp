#include "oracle/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <vector>

namespace iso::oracle {

namespace {

// Nearest-rank percentile: the smallest value with at least p of the samples at or below it.
double percentile(std::vector<double>& v, double p) {
    if (v.empty()) return 0.0;
    const auto rank = std::size_t(std::ceil(p * double(v.size())));
    const std::size_t i = std::clamp<std::size_t>(rank, 1, v.size()) - 1;
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(i), v.end());
    return v[i];
}

bool noId(uint64_t id) {
    return id == UINT64_MAX || id == 0xFFFFFFFFull;
}

} // namespace

Metrics compare(const Image& ref, const Volume& vol, std::span<const float> depth,
                std::span<const uint64_t> ids, std::span<const glm::vec3> normals) {
    const std::size_t pixels = std::size_t(ref.width) * std::size_t(ref.height);
    if (ref.hits.size() != pixels || depth.size() != pixels || (!ids.empty() && ids.size() != pixels) ||
        (!normals.empty() && normals.size() != pixels))
        throw std::invalid_argument("oracle::compare: image sizes differ");

    const double voxel = std::min({vol.spacing.x, vol.spacing.y, vol.spacing.z});
    Metrics m;
    m.pixels = pixels;
    uint64_t hitMiss = 0, idBad = 0;
    std::vector<double> depthErr, normalErr;
    for (std::size_t p = 0; p < pixels; ++p) {
        const Hit& h = ref.hits[p];
        const float d = depth[p];
        const bool finite = std::isfinite(d);
        if (!finite) ++m.nonFinite;
        const bool gpuHit = !(d < 0.0f); // NaN compares false: a broken hit, not a miss
        if (gpuHit != h.hit) ++hitMiss;
        if (!gpuHit || !h.hit) continue;

        ++m.bothHit;
        if (finite) {
            const double e = std::abs(double(d) - h.t) / voxel;
            if (depthErr.empty() || e > m.depthMax) {
                m.depthMax = e;
                m.worstX = int(p % std::size_t(ref.width));
                m.worstY = int(p / std::size_t(ref.width));
            }
            depthErr.push_back(e);
        }
        if (!ids.empty() && (noId(ids[p]) || ids[p] != h.cellId)) ++idBad;
        if (!normals.empty()) {
            const glm::dvec3 n(normals[p]);
            const double gl = glm::length(h.gradient);
            if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z)) {
                if (finite) ++m.nonFinite; // one count per pixel
            } else if (gl > 0.0) {
                const double c = glm::dot(glm::normalize(n), -h.gradient / gl);
                normalErr.push_back(glm::degrees(std::acos(std::clamp(c, -1.0, 1.0))));
            }
        }
    }
    m.hitMissMismatch = pixels ? double(hitMiss) / double(pixels) : 0.0;
    m.depthP50 = percentile(depthErr, 0.50);
    m.depthP99 = percentile(depthErr, 0.99);
    m.idMismatch = ids.empty() ? std::numeric_limits<double>::quiet_NaN()
                               : (m.bothHit ? double(idBad) / double(m.bothHit) : 0.0);
    m.normalP99Deg = normals.empty() ? std::numeric_limits<double>::quiet_NaN() : percentile(normalErr, 0.99);
    return m;
}

std::string format(const Metrics& m) {
    char buf[384];
    std::snprintf(
        buf, sizeof buf,
        "pixels %llu, both hit %llu, hit/miss mismatch %.4f%%, depth p50 %.3g p99 %.3g max %.3g vox at "
        "(%d,%d), id mismatch %.4f%%, normal p99 %.3g deg, non-finite %llu",
        (unsigned long long)m.pixels, (unsigned long long)m.bothHit, 100.0 * m.hitMissMismatch, m.depthP50,
        m.depthP99, m.depthMax, m.worstX, m.worstY, 100.0 * m.idMismatch, m.normalP99Deg,
        (unsigned long long)m.nonFinite);
    return buf;
}

} // namespace iso::oracle
