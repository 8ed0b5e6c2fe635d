// The speed-colour map of CEIR (paper §4.1-4.2): the colour a ray accumulates while it crosses the
// transitional section behind an isosurface, as a function of how fast it crosses it.
//
// speed = v' / densityFactor, where v' is the directional derivative of the scan's value along the unit
// ray (scan units per world unit) at the hit and densityFactor = deltaV / s0 (s0: the standard sample
// distance the transfer function's opacities are given for). The section is then deltaV / v' = s0 / speed
// deep. densityFactor is the renderer's to choose and only ever scales speed: the map itself is over speed,
// so changing densityFactor (or the volume's spacing) never requires rebuilding it.
#pragma once

#include "colour/transfer_function.hpp"

#include <glm/glm.hpp>

#include <optional>
#include <vector>

namespace iso {

// m + 1 entries: entry j holds C(speed_j) with speed_j = -ln(1 - j/m), so entry 0 is the speed -> 0 limit
// and entry m the speed -> infinity limit (the colour at x = 1). rgb in xyz, w = 1.
// Accuracy of the lookup: second order in 1/m below speed_(m-1) = ln m, but in the last interval
// [ln m, infinity) C behaves like c(1) + K/speed while the map is linear in e^-speed, which costs up to
// ~0.1 |K| (about 5/255 for a 0 -> 1 opacity ramp) and shrinks only like 1/ln m (tests/test_colour.cpp).
struct SpeedColourMap {
    int m = 0;
    std::vector<glm::vec4> entries;
};

// deltaV / minSpacing: the transfer function's opacities then hold for one step of the finest voxel
// spacing. Throws std::invalid_argument unless both are positive and finite.
double defaultDensityFactor(double deltaV, double minSpacing);

// C(speed), evaluated directly in double: the n = tf.samples midpoint samples x_i = (i + 0.5) / n of the
// section blended front to back with opacities corrected to the crossing speed, plus the light that gets
// through, with the colour at x = 1 (the opaque interior). speed <= 0 and NaN give the speed -> 0 limit;
// +infinity gives the colour at x = 1. Never NaN for a valid tf.
glm::dvec3 blendColour(const LocalTransferFunction& tf, double speed);

// speed_j = -ln(1 - j/m), the speed entry j of the map was built for (+infinity at j = m).
double mapSpeed(int j, int m);

// u = m (1 - e^-speed) in [0, m]; speed <= 0 and NaN give 0. Inverse of mapSpeed.
double speedToMapCoord(double speed, int m);

// Throws std::invalid_argument for m < 1 or tf.samples < 1.
SpeedColourMap buildSpeedColourMap(const LocalTransferFunction& tf, int m = 256);

// The map's colour at speed: linear between entries floor(u) and floor(u) + 1 (u from speedToMapCoord),
// the same formula as rcSpeedColour in shaders/shared/ceir.h.
glm::dvec3 lookup(const SpeedColourMap& map, double speed);

// Keeps the last map and rebuilds it only when the transfer function (points, deltaV, samples) or m
// changes. densityFactor is not an input: it enters through speed (see above).
class SpeedColourMapCache {
  public:
    const SpeedColourMap& get(const LocalTransferFunction& tf, int m = 256);
    // Whether the last get() built a new map (so the renderer knows to upload it again).
    bool rebuiltLastCall() const { return rebuilt_; }

  private:
    std::optional<LocalTransferFunction> tf_;
    SpeedColourMap map_;
    bool rebuilt_ = false;
};

} // namespace iso
