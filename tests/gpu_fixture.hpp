// One Vulkan context per test process (ctest runs each case in its own process), always with the
// validation layers on, so every GPU test also checks that they reported nothing.
#pragma once

#include "render/renderer.hpp"
#include "vk/context.hpp"

#include <memory>

namespace iso::test {

inline vk::Context& gpu() {
    static std::unique_ptr<vk::Context> ctx = [] {
        vk::ContextOptions options;
        options.validation = true;
        return std::make_unique<vk::Context>(options);
    }();
    return *ctx;
}

// A camera on a circle around the volume's centre, for views other than the default front one.
inline Camera orbitCamera(const Volume& vol, double azimuthDeg, double elevationDeg,
                          double distanceScale = 2.2) {
    glm::dvec3 lo = vol.worldOf(glm::dvec3(0.0));
    glm::dvec3 hi = vol.worldOf(glm::dvec3(vol.dims[0] - 1.0, vol.dims[1] - 1.0, vol.dims[2] - 1.0));
    glm::dvec3 centre = 0.5 * (lo + hi);
    double r = 0.5 * glm::length(hi - lo);
    double az = glm::radians(azimuthDeg), el = glm::radians(elevationDeg);
    Camera cam;
    cam.target = centre;
    cam.eye = centre + distanceScale * r *
                           glm::dvec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    cam.up = {0.0, 0.0, 1.0};
    cam.fovyDeg = 30.0;
    return cam;
}

} // namespace iso::test
