// Synthetic volumes with known surfaces, for testing the oracle and the GPU ray core against it.
// Every generator fills data, type, dims, spacing, origin, directions and the value range.
#pragma once

#include "io/volume.hpp"
#include "scene/camera.hpp"

#include <glm/glm.hpp>

#include <array>

namespace iso::analytic {

struct Scene {
    Volume vol;
    double iso = 0.0; // in stored units
};

// f = radius - |p - centre| in world units, so the surface is (nearly: trilinear interpolation of a
// distance field is not a sphere, and lies slightly inside it) the sphere of `radius` about `centre`.
// F32 stores f and iso is 0. Integer types store round((f + offset) * scale), with offset and scale
// chosen so that the samples span the type's whole range; iso = offset * scale is f = 0 in those units.
struct SphereScene {
    Volume vol;
    double iso = 0.0;
    glm::dvec3 centre{0.0}; // world
    double radius = 0.0;    // world
    double offset = 0.0, scale = 1.0;
};

// n^3 samples with the given spacing, identity directions, origin 0; centre = centre of the world box.
SphereScene sphereDistance(int n, double radius, glm::dvec3 spacing = {1.0, 1.0, 1.0},
                           VoxelType type = VoxelType::F32);
// The same on a skewed scan geometry: spacing (0.8, 1.3, 2.0), directions rotated 30 degrees about z,
// origin (-12.5, 30, 7).
SphereScene sphereAnisotropic(int n, double radius, VoxelType type = VoxelType::F32);
// sphereDistance quantised to u16 over 0..65535; iso is fractional, in stored units.
SphereScene sphereU16(int n, double radius);

// Smallest t >= 0 where the ray meets the exact sphere (the exit if the origin is inside), -1 if none.
double analyticSphereT(const Ray& ray, const glm::dvec3& centre, double radius);

// The Marschner-Lobb test signal (fM = 6, alpha = 0.25) on [-1,1]^3 with n samples per axis, F32.
// Its values lie in [0, 1]; iso 0.5.
Scene marschnerLobb(int n);

// f = dot(gradient, p) at sample p = (i, j, k) (spacing 1, origin 0, identity directions), so the
// interpolant reproduces it exactly and every isosurface is a plane. Integer types store round(f),
// clamped to the type's range.
Volume linearRamp(std::array<uint32_t, 3> dims, glm::dvec3 gradient, VoxelType type = VoxelType::F32);

// Three concentric shells: f = -(r - r0)(r - r1)(r - r2) / r2^3 with r = |p - centre| (world, spacing 1,
// centre of the box), radii sorted ascending, F32, iso 0. Outside the outer shell f < 0, and the sign
// alternates inwards, so a ray towards the centre crosses the outer, middle, inner shell once each.
struct ShellScene {
    Volume vol;
    double iso = 0.0;
    glm::dvec3 centre{0.0};
    std::array<double, 3> radii{};
};
ShellScene nestedShells(int n, std::array<double, 3> radii);

} // namespace iso::analytic
