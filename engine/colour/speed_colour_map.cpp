#include "colour/speed_colour_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace iso {

double defaultDensityFactor(double deltaV, double minSpacing) {
    if (!(std::isfinite(deltaV) && deltaV > 0.0))
        throw std::invalid_argument("densityFactor: deltaV must be positive and finite");
    if (!(std::isfinite(minSpacing) && minSpacing > 0.0))
        throw std::invalid_argument("densityFactor: the voxel spacing must be positive and finite");
    return deltaV / minSpacing;
}

glm::dvec3 blendColour(const LocalTransferFunction& tf, double speed) {
    const int n = tf.samples;
    if (n < 1) throw std::invalid_argument("blendColour: samples must be at least 1");
    // Each sample stands for a slab deltaL / n = s0 / (n speed) deep, so its opacity is the transfer
    // function's (given for s0) corrected to that depth: 1 - (1 - alphaT)^(1 / (n speed)).
    // The paper writes alphaT^(1 / (n speed)), which reads alphaT as a transparency and contradicts its
    // own text (alphaT is the transfer function's opacity); with it a faster crossing would make the
    // section more opaque. The form used here is the standard opacity correction, the one under which
    // the blend is a Riemann sum of the volume-rendering integral and CEIR converges to full volume
    // rendering of the same transfer function as n grows.
    // speed <= 0 and NaN take the speed -> 0 limit; +infinity gives exponent 0 (nothing absorbed).
    const bool slow = !(speed > 0.0);
    const double exponent = slow ? 0.0 : 1.0 / (double(n) * speed);
    glm::dvec3 colour(0.0);
    double transmittance = 1.0;
    for (int i = 0; i < n && transmittance > 0.0; ++i) {
        const double x = (double(i) + 0.5) / double(n);
        const double alphaT = tf.alphaAt(x);
        double alpha;
        if (alphaT <= 0.0) {
            alpha = 0.0; // an exactly transparent sample stays transparent at any speed
        } else if (alphaT >= 1.0 || slow) {
            alpha = 1.0; // an opaque sample, or an infinitely deep slab of a non-transparent one
        } else {
            // log1p/expm1 keep small opacities (fast crossings) accurate; a tiny speed makes the
            // product -infinity, and expm1(-inf) = -1 gives exactly 1.
            alpha = -std::expm1(std::log1p(-alphaT) * exponent);
        }
        colour += transmittance * alpha * tf.rgbAt(x);
        transmittance *= 1.0 - alpha;
    }
    // Whatever gets through the section meets the opaque interior (values above iso + deltaV).
    return colour + transmittance * tf.rgbAt(1.0);
}

double mapSpeed(int j, int m) {
    if (j >= m) return std::numeric_limits<double>::infinity();
    if (j <= 0) return 0.0;
    return -std::log1p(-double(j) / double(m));
}

double speedToMapCoord(double speed, int m) {
    if (!(speed > 0.0)) return 0.0;
    const double u = -double(m) * std::expm1(-speed); // expm1(-inf) = -1: u = m
    return std::clamp(u, 0.0, double(m));
}

SpeedColourMap buildSpeedColourMap(const LocalTransferFunction& tf, int m) {
    if (m < 1)
        throw std::invalid_argument("buildSpeedColourMap: m must be at least 1, got " + std::to_string(m));
    if (tf.samples < 1) throw std::invalid_argument("buildSpeedColourMap: samples must be at least 1");
    SpeedColourMap map;
    map.m = m;
    map.entries.resize(std::size_t(m) + 1);
    for (int j = 0; j <= m; ++j)
        map.entries[std::size_t(j)] = glm::vec4(glm::vec3(blendColour(tf, mapSpeed(j, m))), 1.0f);
    return map;
}

glm::dvec3 lookup(const SpeedColourMap& map, double speed) {
    if (map.m < 1 || map.entries.size() != std::size_t(map.m) + 1)
        throw std::invalid_argument("lookup: the map must hold m + 1 entries");
    const double u = speedToMapCoord(speed, map.m);
    const int j = std::min(int(std::floor(u)), map.m - 1);
    const double f = u - double(j);
    const glm::dvec3 a(map.entries[std::size_t(j)]);
    const glm::dvec3 b(map.entries[std::size_t(j) + 1]);
    return a + (b - a) * f;
}

const SpeedColourMap& SpeedColourMapCache::get(const LocalTransferFunction& tf, int m) {
    rebuilt_ = false;
    if (!(tf_ && *tf_ == tf && map_.m == m)) {
        // Build first, so a throw leaves the previous map and its inputs in place.
        SpeedColourMap fresh = buildSpeedColourMap(tf, m);
        map_ = std::move(fresh);
        tf_ = tf;
        rebuilt_ = true;
    }
    return map_;
}

} // namespace iso
