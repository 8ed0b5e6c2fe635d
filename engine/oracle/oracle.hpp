// The float64 brute-force reference for isosurface ray casting. It shares no code with the GPU ray
// core on purpose: it is what the ray core is measured against, so it favours obvious correctness
// (dense sampling of every cell, bisection in double) over speed.
//
// What it computes (the contract):
// - The surface is {f = iso} of the trilinear interpolant f of the samples; f >= iso counts as inside.
// - A crossing is a strict sign change of f - iso along the ray, or a point where f - iso is exactly 0
//   (a run of zeros, e.g. through a flat cell, is one crossing at its first point). Entering the box
//   (or starting) already inside is not a crossing by itself.
// - The search covers t >= 0 within the box [0,nx-1]x[0,ny-1]x[0,nz-1] in index space (intersected
//   with Options::crop); t is the world distance along the unit ray direction.
// - A crossing belongs to the first cell along the ray that contains it, so a root exactly on a
//   shared face goes to the cell the ray leaves there, and it counts once.
// - A cell with a non-finite corner holds no surface; the sign history restarts after it.
// - A volume with fewer than 2 samples along any axis has no cells and therefore no hits.
#pragma once

#include "io/volume.hpp"
#include "scene/camera.hpp"

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

namespace iso::oracle {

struct Options {
    double iso = 0.0; // in the volume's stored units
    // Index-space box i0,j0,k0,i1,j1,k1 (may be fractional), intersected with the volume box.
    std::optional<std::array<double, 6>> crop;
    // Return the (skipCrossings+1)-th crossing: every crossing counts once, including several in one cell.
    int skipCrossings = 0;
};

struct Hit {
    bool hit = false;
    double t = -1.0;                // world distance from the ray origin
    std::array<uint32_t, 3> cell{}; // lowest corner of the cell holding the crossing
    uint64_t cellId = UINT64_MAX;   // i + nx*(j + ny*k)
    glm::dvec3 indexPos{0.0};       // continuous index-space position
    glm::dvec3 worldPos{0.0};       // ray.origin + t*ray.dir
    glm::dvec3 gradient{0.0};       // of the trilinear interpolant, world units (points into f >= iso)
    double value = 0.0;             // interpolated value at the hit, stored units
};

Hit trace(const Volume& vol, const Ray& ray, const Options& opt);

struct Image {
    int width = 0, height = 0;
    std::vector<Hit> hits; // row-major, y down from the top row: hits[y*width + x]
};

// One trace() per pixel centre (primaryRay); rows are spread over hardware_concurrency() threads.
Image render(const Volume& vol, const Camera& cam, int width, int height, const Options& opt);

} // namespace iso::oracle
