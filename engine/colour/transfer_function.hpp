// Local transfer functions (paper §4.1): the colour and opacity of the thin transitional section
// [iso, iso + deltaV] directly behind an isosurface, from which CEIR derives the surface's material colour.
#pragma once

#include <glm/glm.hpp>

#include <filesystem>
#include <vector>

namespace iso {

// One control point. x in [0, 1] is the position inside the transitional section (0: the isovalue,
// 1: isovalue + deltaV); alpha is the opacity for the standard sample distance s0 = deltaV / densityFactor.
struct TfPoint {
    double x = 0.0;
    glm::dvec3 rgb{0.0};
    double alpha = 0.0;

    bool operator==(const TfPoint&) const = default;
};

// Colour and opacity are linear between the points (sorted by strictly increasing x); before the first and
// after the last point the end values hold. Outside the section the scene is transparent below the
// isovalue and opaque above isovalue + deltaV, with the colour at x = 1.
struct LocalTransferFunction {
    double deltaV = 100.0; // width of the transitional section, in the scan's units
    int samples = 64;      // the paper's n: samples of the section blended into each map entry
    std::vector<TfPoint> points;

    // rgb at x; x is clamped to [0, 1] (and NaN reads as 0). Black when there are no points.
    glm::dvec3 rgbAt(double x) const;
    // Opacity at x for the distance s0: 0 below the section (x < 0, and NaN), 1 above it (x > 1).
    double alphaAt(double x) const;

    bool operator==(const LocalTransferFunction&) const = default;
};

// Reads {"delta_v": 100.0, "samples": 64, "points": [{"x": 0.0, "rgb": [r, g, b], "alpha": a}, ...]}.
// delta_v and samples may be left out (100 and 64 then); points is required. Throws iso::InputError
// "<path>: <problem>" for a missing or unreadable file, bad JSON, delta_v not a positive finite number,
// samples not an integer in [1, 4096], no points, x outside [0, 1] or not strictly increasing, rgb not
// three numbers in [0, 1], or alpha outside [0, 1].
LocalTransferFunction loadTransferFunction(const std::filesystem::path& path);

// Throws std::invalid_argument naming the first problem (the same checks the loader makes); lets code
// that builds a function by hand check it before rendering with it.
void validate(const LocalTransferFunction& tf);

// A function that reads well on CT without any file: a skin/bone-like surface (see the .cpp for why).
LocalTransferFunction defaultTransferFunction();

// rgb in xyz and alpha (for s0) in w at x = k / (entries - 1), k = 0 .. entries - 1: the lookup table of
// the full-volume-rendering pass (rcTransferAt in ceir.h interpolates it). entries >= 2.
std::vector<glm::vec4> tabulate(const LocalTransferFunction& tf, int entries);

} // namespace iso
