// The view: perspective or orthographic, as the --camera JSON contract describes (README, "Cameras").
#pragma once

#include <glm/glm.hpp>

#include <filesystem>

namespace iso {

struct Volume;

struct Camera {
    glm::dvec3 eye{0.0, 0.0, 1.0};
    glm::dvec3 target{0.0};
    glm::dvec3 up{0.0, 0.0, 1.0};
    double fovyDeg = 30.0;
    bool orthographic = false;
    double height = 1.0; // visible height in world units, orthographic only
};

// A ray in world space; dir has unit length, so ray parameters are world distances.
struct Ray {
    glm::dvec3 origin;
    glm::dvec3 dir;
};

// Ray through the centre of pixel (x, y) of a width x height image; x right, y down from the top row.
// Perspective rays start at the eye; orthographic rays on the plane through the eye perpendicular to the
// view.
Ray primaryRay(const Camera& cam, int width, int height, int x, int y);

// Reads {"eye":[..],"target":[..],"up":[..],"fovy_deg":30} or with "projection":"orthographic","height":h.
Camera loadCamera(const std::filesystem::path& path);

// A view of the whole volume from the front (anterior, LPS -y) with superior (+z) up.
Camera frameVolume(const Volume& vol, int width, int height);

} // namespace iso
