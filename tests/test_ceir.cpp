// Colour-enhanced isosurface rendering (CEIR, paper §4) and the full-volume-rendering reference (§6) on the
// GPU: on ramps seen along their gradient, the shallow CEIR colour and the FVR colour against the continuous
// volume-rendering integral through the transitional section, computed here independently of
// engine/colour; deep CEIR's choice of the mean derivative over the section; golden images of the bundled
// head in every colour mode.
#include "golden.hpp"
#include "gpu_fixture.hpp"

#include "io/image_write.hpp"
#include "oracle/analytic.hpp"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace iso;

namespace {

constexpr double kColourTol = 6.0 / 255.0;

double maxChannelDiff(glm::dvec3 a, glm::dvec3 b) {
    glm::dvec3 d = glm::abs(a - b);
    return std::max(d.x, std::max(d.y, d.z));
}

glm::dvec3 rgbAt(const Frame& f, int x, int y) {
    const std::size_t p = 4 * (std::size_t(y) * std::size_t(f.width) + std::size_t(x));
    return {f.rgba[p], f.rgba[p + 1], f.rgba[p + 2]};
}

double alphaAt(const Frame& f, int x, int y) {
    return f.rgba[4 * (std::size_t(y) * std::size_t(f.width) + std::size_t(x)) + 3];
}

uint64_t nonFinite(const Frame& f) {
    uint64_t n = 0;
    for (float v : f.rgba) n += std::isfinite(v) ? 0 : 1;
    for (float v : f.depth) n += std::isfinite(v) ? 0 : 1;
    return n;
}

// The local transfer function's colour and opacity at x, piecewise linear between the points with the end
// values held outside them: written out here so the integral below does not lean on engine/colour.
glm::dvec4 tfAt(const LocalTransferFunction& tf, double x) {
    const auto& pts = tf.points;
    auto value = [](const TfPoint& p) { return glm::dvec4(p.rgb, p.alpha); };
    if (x <= pts.front().x) return value(pts.front());
    if (x >= pts.back().x) return value(pts.back());
    std::size_t i = 0;
    while (i + 1 < pts.size() && pts[i + 1].x <= x) ++i;
    const double f = (x - pts[i].x) / (pts[i + 1].x - pts[i].x);
    return glm::mix(value(pts[i]), value(pts[i + 1]), f);
}

// The continuous volume-rendering integral through the transitional section [iso, iso + deltaV] crossed at
// the constant derivative vPrime (scan units per world unit):
//   C = int_0^dl c(x(l)) sigma(x(l)) exp(-int_0^l sigma) dl + T(dl) c(1),
//   sigma(x) = -ln(1 - alphaT(x)) / s0, x(l) = l / dl, dl = deltaV / vPrime, s0 = deltaV / densityFactor,
// by the midpoint rule on N steps in l (the optical depth at each midpoint is the depth accumulated before
// the step plus half the step's own). With alphaT -> 1 at x = 1, sigma has an integrable logarithmic
// singularity there, which the midpoint rule never evaluates.
glm::dvec3 sectionIntegral(const LocalTransferFunction& tf, double densityFactor, double vPrime) {
    const double s0 = tf.deltaV / densityFactor;
    const double dl = tf.deltaV / vPrime;
    constexpr int N = 50000;
    const double h = dl / N;
    glm::dvec3 colour(0.0);
    double depth = 0.0;
    for (int k = 0; k < N; ++k) {
        const double l = (k + 0.5) * h;
        const glm::dvec4 ca = tfAt(tf, l / dl);
        if (ca.w >= 1.0) { // opaque before the end of the section: all that is left stops here
            colour += glm::dvec3(ca) * std::exp(-depth);
            return colour;
        }
        const double sigma = -std::log1p(-ca.w) / s0;
        colour += glm::dvec3(ca) * sigma * std::exp(-(depth + 0.5 * sigma * h)) * h;
        depth += sigma * h;
    }
    return colour + std::exp(-depth) * glm::dvec3(tfAt(tf, 1.0));
}

// A ramp f = vPrime * x (world x) seen along +x by an orthographic camera from outside (x < 0), its
// isosurface the plane x = isoX.
struct RampScene {
    Volume vol;
    Camera cam;
    double iso = 0.0;
    double tIso = 0.0; // world distance from the eye plane to the isosurface
};

constexpr double kEyeX = -2.0;

Camera alongX(const Volume& vol) {
    Camera cam;
    const double cy = 0.5 * (vol.dims[1] - 1.0) * vol.spacing.y,
                 cz = 0.5 * (vol.dims[2] - 1.0) * vol.spacing.z;
    cam.orthographic = true;
    cam.height = 4.0;
    cam.eye = {kEyeX, cy, cz};
    cam.target = {10.0, cy, cz};
    cam.up = {0.0, 0.0, 1.0};
    return cam;
}

// spacingX scales world x; linearRamp's index slope is vPrime * spacingX so that f = vPrime * world x.
RampScene rampAlongX(double vPrime, double spacingX, uint32_t nx, double isoX) {
    RampScene s;
    s.vol = analytic::linearRamp({nx, 8, 8}, {vPrime * spacingX, 0.0, 0.0}, VoxelType::F32);
    s.vol.spacing = {spacingX, 1.0, 1.0};
    s.cam = alongX(s.vol);
    s.iso = vPrime * isoX;
    s.tIso = isoX - kEyeX;
    return s;
}

// f(x) = a x up to x = kinkX, then slope b: the derivative changes just behind the surface. Samples at
// x = i * spacingX (kinkX / spacingX an integer, so the trilinear interpolant is exactly this polyline).
Volume kinkedRamp(double a, double b, double kinkX, double spacingX, uint32_t nx) {
    Volume vol;
    vol.dims = {nx, 8, 8};
    vol.spacing = {spacingX, 1.0, 1.0};
    vol.type = VoxelType::F32;
    vol.source = "kinked ramp";
    vol.data.resize(vol.byteSize());
    for (uint32_t k = 0; k < vol.dims[2]; ++k)
        for (uint32_t j = 0; j < vol.dims[1]; ++j)
            for (uint32_t i = 0; i < nx; ++i) {
                const double x = i * spacingX;
                const float v = float(x <= kinkX ? a * x : a * kinkX + b * (x - kinkX));
                std::memcpy(vol.data.data() + vol.index(i, j, k) * sizeof(float), &v, sizeof v);
            }
    vol.computeRange();
    return vol;
}

constexpr int kRampPixels = 16;

RenderSettings rampSettings(const Camera& cam, double iso, RenderMode mode, double densityFactor) {
    RenderSettings s;
    s.width = s.height = kRampPixels;
    s.camera = cam;
    s.iso = iso;
    s.mode = mode;
    s.shade = false;
    s.tf = defaultTransferFunction();
    s.densityFactor = densityFactor;
    return s;
}

// The largest colour difference from `want` over the central half of the image (all of which sees the
// plane); every such pixel must be a hit (alpha ~ 1).
double centralMaxDiff(const Frame& f, glm::dvec3 want, double minAlpha) {
    double worst = 0.0;
    for (int y = f.height / 4; y < 3 * f.height / 4; ++y)
        for (int x = f.width / 4; x < 3 * f.width / 4; ++x) {
            CHECK(alphaAt(f, x, y) >= minAlpha);
            worst = std::max(worst, maxChannelDiff(rgbAt(f, x, y), want));
        }
    return worst;
}

std::string str(glm::dvec3 c) {
    std::ostringstream out;
    out << "(" << c.x << ", " << c.y << ", " << c.z << ")";
    return out.str();
}

// densityFactor 25 with deltaV 100: s0 = 4 world units. Derivatives 6.25 and 62.5 (10x apart) are speeds
// 0.25 and 2.5, sections 16 and 1.6 world units deep, both far from the map's inaccurate end at infinity.
constexpr double kDensity = 25.0;
constexpr double kSlowSlope = 6.25, kFastSlope = 62.5;
constexpr double kIsoX = 4.3;

struct Geometry {
    double spacingX;
    uint32_t nx;
};
// Unit spacing, and a finer x spacing (world units fixed, so the slopes per index halve): the section of
// the slow ramp (to x = 20.3) ends inside both boxes (31 and 23.5 world units long).
constexpr Geometry kGeometries[] = {{1.0, 32}, {0.5, 48}};

} // namespace

TEST_CASE("ceir: shallow colour on a ramp equals the volume-rendering integral through the section") {
    Renderer renderer(test::gpu());
    const LocalTransferFunction tf = defaultTransferFunction();
    const glm::dvec3 slowWant = sectionIntegral(tf, kDensity, kSlowSlope);
    const glm::dvec3 fastWant = sectionIntegral(tf, kDensity, kFastSlope);
    MESSAGE("integral: slow " << str(slowWant) << ", fast " << str(fastWant) << ", apart "
                              << maxChannelDiff(slowWant, fastWant) * 255.0 << "/255");
    CHECK(maxChannelDiff(slowWant, fastWant) > 20.0 / 255.0);
    for (const Geometry& g : kGeometries) {
        glm::dvec3 got[2];
        int n = 0;
        for (double slope : {kSlowSlope, kFastSlope}) {
            CAPTURE(g.spacingX);
            CAPTURE(slope);
            RampScene sc = rampAlongX(slope, g.spacingX, g.nx, kIsoX);
            renderer.setVolume(sc.vol);
            Frame f = renderer.render(rampSettings(sc.cam, sc.iso, RenderMode::CeirShallow, kDensity),
                                      {true, true, false});
            const glm::dvec3 want = sectionIntegral(tf, kDensity, slope);
            const double worst = centralMaxDiff(f, want, 1.0);
            MESSAGE("shallow, spacing " << g.spacingX << ", v' " << slope << ": got " << str(rgbAt(f, 8, 8))
                                        << ", integral " << str(want) << ", max diff " << worst * 255.0
                                        << "/255");
            CHECK(worst <= kColourTol);
            // The hit is the plane x = isoX: depth is the distance from the eye plane.
            CHECK(std::abs(f.depth[8 * kRampPixels + 8] - sc.tIso) < 1e-3);
            CHECK(nonFinite(f) == 0);
            got[n++] = rgbAt(f, 8, 8);
        }
        CHECK(maxChannelDiff(got[0], got[1]) > 20.0 / 255.0);
    }

    // The same renderer with another transfer function, then another map size: the map follows both.
    RampScene sc = rampAlongX(kSlowSlope, 1.0, 32, kIsoX);
    renderer.setVolume(sc.vol);
    RenderSettings s = rampSettings(sc.cam, sc.iso, RenderMode::CeirShallow, kDensity);
    s.tf.deltaV = 60.0; // speed 6.25 / 25 = 0.25 still; section 9.6 deep
    s.tf.points = {{0.0, {0.1, 0.2, 0.9}, 0.02}, {0.5, {0.2, 0.9, 0.3}, 0.3}, {1.0, {0.9, 0.9, 0.1}, 0.9}};
    const double density = s.tf.deltaV / 4.0; // s0 stays 4
    s.densityFactor = density;
    const glm::dvec3 want = sectionIntegral(s.tf, density, kSlowSlope);
    Frame other = renderer.render(s);
    const double otherErr = centralMaxDiff(other, want, 1.0);
    s.mapIntervals = 16;
    Frame coarse = renderer.render(s);
    const double coarseVsLookup =
        centralMaxDiff(coarse, lookup(buildSpeedColourMap(s.tf, 16), kSlowSlope / density), 1.0);
    MESSAGE("another tf: got " << str(rgbAt(other, 8, 8)) << ", integral " << str(want) << ", max diff "
                               << otherErr * 255.0 << "/255; m = 16 vs the CPU lookup "
                               << coarseVsLookup * 255.0 << "/255");
    CHECK(otherErr <= kColourTol);
    CHECK(coarseVsLookup <= 1e-4);
    CHECK(nonFinite(other) == 0);
    CHECK(nonFinite(coarse) == 0);
    CHECK(test::gpu().validationMessages() == 0);
}

TEST_CASE("ceir: full volume rendering with a small step matches the same integral") {
    Renderer renderer(test::gpu());
    const LocalTransferFunction tf = defaultTransferFunction();
    const double s0 = tf.deltaV / kDensity;
    for (const Geometry& g : kGeometries) {
        for (double slope : {kSlowSlope, kFastSlope}) {
            CAPTURE(g.spacingX);
            CAPTURE(slope);
            RampScene sc = rampAlongX(slope, g.spacingX, g.nx, kIsoX);
            renderer.setVolume(sc.vol);
            const glm::dvec3 want = sectionIntegral(tf, kDensity, slope);
            for (double step : {s0 / 16.0, s0 / 64.0}) {
                CAPTURE(step);
                RenderSettings s = rampSettings(sc.cam, sc.iso, RenderMode::Fvr, kDensity);
                s.fvrStep = step;
                Frame f = renderer.render(s, {true, true, false});
                // Beyond iso + deltaV everything is opaque, so the remaining transmittance ends at ~0
                // (below the pass's early-termination threshold of 1e-3).
                const double worst = centralMaxDiff(f, want, 0.999);
                MESSAGE("fvr, spacing " << g.spacingX << ", v' " << slope << ", step " << step << " (section "
                                        << tf.deltaV / slope / step << " steps): got " << str(rgbAt(f, 8, 8))
                                        << ", max diff " << worst * 255.0 << "/255");
                CHECK(worst <= kColourTol);
                // Depth: the first sample with any opacity, within one step behind the isosurface.
                const double d = f.depth[8 * kRampPixels + 8];
                CHECK(d >= sc.tIso - 1e-4);
                CHECK(d <= sc.tIso + step + 1e-4);
                CHECK(nonFinite(f) == 0);
            }
        }
    }
    CHECK(test::gpu().validationMessages() == 0);
}

TEST_CASE("ceir: deep mode takes the mean derivative over the section, shallow the one at the surface") {
    Renderer renderer(test::gpu());
    const LocalTransferFunction tf = defaultTransferFunction();
    struct Kink {
        double a, b;   // slopes before and after the kink (world units)
        double before; // distance from the surface to the kink, < deltaV / a
    };
    // Slow then fast, and fast then slow; the kink is more than one x spacing behind the surface so the
    // central-difference gradient at the hit sees slope a alone.
    const Kink kinks[] = {{10.0, 100.0, 1.5}, {50.0, 5.0, 1.2}};
    constexpr double kinkX = 8.0;
    for (const Geometry& g : kGeometries) {
        for (const Kink& k : kinks) {
            CAPTURE(g.spacingX);
            CAPTURE(k.a);
            CAPTURE(k.b);
            Volume vol = kinkedRamp(k.a, k.b, kinkX, g.spacingX, g.nx);
            renderer.setVolume(vol);
            const double isoX = kinkX - k.before;
            const double iso = k.a * isoX;
            const double dl = k.before + (tf.deltaV - k.a * k.before) / k.b; // the section's actual depth
            REQUIRE(isoX + dl < (g.nx - 1) * g.spacingX - 1.0);
            const double mean = tf.deltaV / dl;
            const glm::dvec3 deepWant = blendColour(tf, mean / kDensity);
            const glm::dvec3 shallowWant = blendColour(tf, k.a / kDensity);
            RenderSettings s = rampSettings(alongX(vol), iso, RenderMode::CeirDeep, kDensity);
            s.deepReach = 20.0; // world units: the default (16 smallest spacings) is 8 for spacing 0.5
            Frame deep = renderer.render(s);
            s.mode = RenderMode::CeirShallow;
            Frame shallow = renderer.render(s);
            const double deepErr = centralMaxDiff(deep, deepWant, 1.0);
            const double shallowErr = centralMaxDiff(shallow, shallowWant, 1.0);
            const double apart = maxChannelDiff(rgbAt(deep, 8, 8), rgbAt(shallow, 8, 8));
            MESSAGE("deep, spacing " << g.spacingX << ", slopes " << k.a << " -> " << k.b << ": mean v' "
                                     << mean << ", |deep - C(mean)| " << deepErr * 255.0
                                     << "/255, |shallow - C(a)| " << shallowErr * 255.0
                                     << "/255, deep vs shallow " << apart * 255.0 << "/255");
            CHECK(deepErr <= kColourTol);
            CHECK(shallowErr <= kColourTol);
            CHECK(apart > 10.0 / 255.0);
            CHECK(nonFinite(deep) == 0);
            CHECK(nonFinite(shallow) == 0);
        }
    }
    {
        // A section deeper than the reach shows the mean derivative over the reach (iso_pixel.h).
        // Fast then slow: 60 units in the first 1.2, then 5 per unit; a reach of 4 ends before iso + deltaV.
        Volume vol = kinkedRamp(50.0, 5.0, kinkX, 1.0, 32);
        renderer.setVolume(vol);
        RenderSettings s = rampSettings(alongX(vol), 50.0 * (kinkX - 1.2), RenderMode::CeirDeep, kDensity);
        s.deepReach = 4.0;
        Frame deep = renderer.render(s);
        const double mean = (60.0 + 5.0 * (4.0 - 1.2)) / 4.0;
        const double err = centralMaxDiff(deep, blendColour(tf, mean / kDensity), 1.0);
        MESSAGE("reach 4: mean v' over the reach " << mean << ", diff " << err * 255.0 << "/255");
        CHECK(err <= kColourTol);
        CHECK(nonFinite(deep) == 0);
    }
    CHECK(test::gpu().validationMessages() == 0);
}

TEST_CASE("ceir: the bundled head matches its golden images in every colour mode") {
    const std::filesystem::path src = ISOSCOPE_SOURCE_DIR;
    Volume vol = loadVolume(src / "data/headsq_quarter.nhdr");
    Renderer renderer(test::gpu());
    renderer.setVolume(vol);
    std::vector<Frame> frames;
    for (RenderMode mode : {RenderMode::CeirShallow, RenderMode::CeirDeep, RenderMode::Fvr}) {
        const std::string mode_name = modeName(mode);
        CAPTURE(mode_name);
        RenderSettings s;
        s.width = s.height = 96;
        s.iso = 500.0;
        s.camera = loadCamera(src / "data/headsq_quarter.camera.json");
        s.mode = mode;
        Frame f = renderer.render(s);
        CHECK(nonFinite(f) == 0);
        const std::string name = std::string("headsq_") + modeName(mode) + "_96";
        test::checkGolden(
            name,
            std::string("data/headsq_quarter.nhdr, iso 500, data/headsq_quarter.camera.json, 96x96, ") +
                modeName(mode) + ", default transfer function",
            f);
        frames.push_back(std::move(f));
    }
    // For the record (no target): how far each CEIR image is from the FVR it approximates, over pixels
    // both render opaque.
    for (int m = 0; m < 2; ++m) {
        double sum = 0.0, worst = 0.0;
        int n = 0;
        for (std::size_t p = 0; p < frames[2].rgba.size() / 4; ++p) {
            if (frames[size_t(m)].rgba[4 * p + 3] < 1.0f || frames[2].rgba[4 * p + 3] < 0.999f) continue;
            double d = 0.0;
            for (int c = 0; c < 3; ++c)
                d = std::max(d,
                             double(std::abs(frames[size_t(m)].rgba[4 * p + c] - frames[2].rgba[4 * p + c])));
            sum += d, worst = std::max(worst, d), ++n;
        }
        MESSAGE(std::string(m == 0 ? "shallow" : "deep")
                << " vs fvr on the head: " << n << " pixels, mean " << sum / std::max(n, 1) * 255.0
                << "/255, max " << worst * 255.0 << "/255 (linear)");
    }
    CHECK(test::gpu().validationMessages() == 0);
}
