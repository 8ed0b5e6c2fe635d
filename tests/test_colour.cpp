// CEIR's colour model (engine/colour and shaders/shared/ceir.h): the speed-colour map against a direct
// evaluation, the shader's lookup against the CPU's, the blend against an independent evaluation of the
// continuous volume-rendering integral, and the transfer-function file format.
#include "colour/speed_colour_map.hpp"
#include "colour/transfer_function.hpp"
#include "io/volume.hpp"

#include "temp_dir.hpp"

#include <doctest/doctest.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace iso::rc {
// ceir.h's hooks: tests point them at the map and the table they build.
inline std::vector<glm::vec4> gColourTestMap;
inline std::vector<glm::vec4> gColourTestTable;
inline glm::vec4 rcSpeedColourEntry(int j) {
    return gColourTestMap.at(std::size_t(j));
}
inline glm::vec4 rcTransferEntry(int k) {
    return gColourTestTable.at(std::size_t(k));
}
} // namespace iso::rc

#include "ceir.h"

namespace fs = std::filesystem;
using namespace iso;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The contract's example: a yellow-to-blue ramp whose opacity rises linearly from 0 to 1.
LocalTransferFunction rampTf(int samples = 64) {
    LocalTransferFunction tf;
    tf.deltaV = 100.0;
    tf.samples = samples;
    tf.points = {{0.0, {1.0, 0.9, 0.2}, 0.0}, {1.0, {0.2, 0.2, 0.9}, 1.0}};
    return tf;
}

double maxDiff(glm::dvec3 a, glm::dvec3 b) {
    glm::dvec3 d = glm::abs(a - b);
    return std::max(d.x, std::max(d.y, d.z));
}

bool finite(glm::dvec3 c) {
    return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z);
}

// count speeds log-spaced over [1e-3, 1e3].
std::vector<double> logSpeeds(int count) {
    std::vector<double> s(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i) s[std::size_t(i)] = std::pow(10.0, -3.0 + 6.0 * i / (count - 1));
    return s;
}

const char* const kExample = R"({"delta_v": 100.0, "samples": 64, "points": [
    {"x": 0.0, "rgb": [1, 0.9, 0.2], "alpha": 0.0},
    {"x": 0.25, "rgb": [0.8, 0.5, 0.3], "alpha": 0.4},
    {"x": 1.0, "rgb": [0.2, 0.2, 0.9], "alpha": 1.0}]})";

// The map is exact at its entries; between them it interpolates linearly in u = m (1 - e^-speed).
//  - For u < m - 1, C(u / m) is smooth, so the error is at most max|C''| / 8 per interval: second order,
//    16x smaller for a 4x finer map. The first interval is the worst there when alpha_T(x_0) is small
//    (C changes over speeds ~ alpha_T(x_0) / n, far below 1 / m).
//  - The last interval [ln m, infinity) is not smooth: for large speed C = c(1) + K / speed + O(1 / speed^2),
//    K = sum_i -ln(1 - alpha_T(x_i)) / n (c_i - c(1)), while the map interpolates e^-speed linearly. With
//    speed = ln m + t the error is |K| (1 / (ln m + t) - e^-t / ln m), whose maximum over t (~2.5) is
//    ~0.11 |K| at m = 256 and ~0.094 |K| at m = 1024: it decays only like 1 / ln m. This tail dominates
//    and is a property of the log-sampled map itself (paper §4.2), not of the code.
double tailBound(const LocalTransferFunction& tf, int m) {
    const int n = tf.samples;
    glm::dvec3 k(0.0);
    for (int i = 0; i < n; ++i) {
        const double x = (i + 0.5) / n;
        k += -std::log1p(-tf.alphaAt(x)) / n * (tf.rgbAt(x) - tf.rgbAt(1.0));
    }
    const double kMax = std::max(std::abs(k.x), std::max(std::abs(k.y), std::abs(k.z)));
    const double l = std::log(double(m));
    double g = 0.0;
    for (double t = 0.0; t < 30.0; t += 1e-3) g = std::max(g, 1.0 / (l + t) - std::exp(-t) / l);
    return kMax * g;
}

struct MapErrors {
    double inner = 0.0; // u < m - 1
    double tail = 0.0;  // the last interval
};

MapErrors mapErrors(const LocalTransferFunction& tf, int m) {
    const SpeedColourMap map = buildSpeedColourMap(tf, m);
    MapErrors e;
    for (double s : logSpeeds(4001)) {
        const double d = maxDiff(lookup(map, s), blendColour(tf, s));
        double& slot = speedToMapCoord(s, m) >= m - 1 ? e.tail : e.inner;
        slot = std::max(slot, d);
    }
    return e;
}

} // namespace

TEST_CASE("colour: the speed-colour map matches blendColour, closer for larger m") {
    for (const LocalTransferFunction& tf : {rampTf(), defaultTransferFunction()}) {
        const MapErrors e256 = mapErrors(tf, 256);
        const MapErrors e1024 = mapErrors(tf, 1024);
        MESSAGE("m=256: inner " << e256.inner * 255.0 << "/255, tail " << e256.tail * 255.0 << "/255 (bound "
                                << tailBound(tf, 256) * 255.0 << "/255)");
        MESSAGE("m=1024: inner " << e1024.inner * 255.0 << "/255, tail " << e1024.tail * 255.0
                                 << "/255 (bound " << tailBound(tf, 1024) * 255.0 << "/255)");
        // Inner: 3/255 covers the first interval of the ramp at m = 256 (measured 2.8/255); second order
        // means at least 4x less at m = 1024 (16x expected away from the ends).
        CHECK(e256.inner <= 3.0 / 255.0);
        CHECK(e1024.inner <= e256.inner / 4.0);
        CHECK(e1024.inner <= 0.25 / 255.0);
        // Tail: the asymptotic bound above, with 10% for the O(1 / speed^2) terms; smaller with m.
        CHECK(e256.tail <= 1.1 * tailBound(tf, 256));
        CHECK(e1024.tail <= 1.1 * tailBound(tf, 1024));
        CHECK(e1024.tail < e256.tail);
        CHECK(tailBound(tf, 1024) < tailBound(tf, 256));
        // Overall: within 7/255 at m = 256 and 6/255 at m = 1024 for these functions.
        CHECK(std::max(e256.inner, e256.tail) <= 7.0 / 255.0);
        CHECK(std::max(e1024.inner, e1024.tail) <= 6.0 / 255.0);
    }
}

TEST_CASE("colour: the shader's rcSpeedColour equals the CPU lookup") {
    for (int m : {1, 16, 256, 1024}) {
        const SpeedColourMap map = buildSpeedColourMap(defaultTransferFunction(), m);
        iso::rc::gColourTestMap = map.entries;
        // Float rounding of u moves the result by |du| times the step between neighbouring entries, with
        // |du| ~ m * 2^-24; the float mix adds a few ulps. 1e-5 covers both for m <= 1024.
        double worst = 0.0;
        std::vector<double> speeds = logSpeeds(3001);
        for (double s : {0.0, -1.0, -kInf, kInf, kNaN, 1e-30, 50.0, 88.0, 89.0, 1e30}) speeds.push_back(s);
        for (double s : speeds) {
            const glm::dvec3 gpu(iso::rc::rcSpeedColour(float(s), m));
            const glm::dvec3 cpu = lookup(map, double(float(s)));
            REQUIRE(finite(gpu));
            worst = std::max(worst, maxDiff(gpu, cpu));
        }
        MESSAGE("m=" << m << ": worst |rcSpeedColour - lookup| = " << worst);
        CHECK(worst <= 1e-5);
    }
}

TEST_CASE("colour: speed_j maps back to u = j") {
    for (int m : {1, 7, 256, 1024}) {
        double worstCpu = 0.0, worstGpu = 0.0;
        for (int j = 0; j <= m; ++j) {
            const double speed = mapSpeed(j, m);
            worstCpu = std::max(worstCpu, std::abs(speedToMapCoord(speed, m) - j));
            worstGpu = std::max(worstGpu, std::abs(double(iso::rc::rcSpeedToMapCoord(float(speed), m)) - j));
        }
        MESSAGE("m=" << m << ": worst |u(speed_j) - j| = " << worstCpu << " (double), " << worstGpu
                     << " (float)");
        // Float: u near 1024 has an ulp of 6e-5, and 1 - e^-speed is rounded once before the scaling.
        CHECK(worstCpu <= 1e-9);
        CHECK(worstGpu <= 1e-4);
        CHECK(mapSpeed(0, m) == 0.0);
        CHECK(mapSpeed(m, m) == kInf);
    }
}

TEST_CASE("colour: the limits at speed 0, infinity, NaN and negative speeds") {
    const LocalTransferFunction tf = rampTf();
    const int n = tf.samples;
    // speed -> 0: the first sample with alpha_T > 0 (here the first, at x = 0.5 / n) takes everything.
    const glm::dvec3 slow = tf.rgbAt(0.5 / n);
    // speed -> infinity: the section is infinitely thin; the colour behind it (x = 1) shows.
    const glm::dvec3 fast = tf.rgbAt(1.0);
    for (double s : {0.0, -0.0, -1.0, -kInf, kNaN, 1e-300, 4.9e-324}) {
        CAPTURE(s);
        CHECK(maxDiff(blendColour(tf, s), slow) == 0.0);
    }
    CHECK(maxDiff(blendColour(tf, kInf), fast) == 0.0);
    CHECK(maxDiff(blendColour(tf, 1e300), fast) < 1e-12);
    CHECK(maxDiff(blendColour(tf, std::numeric_limits<double>::max()), fast) < 1e-12);

    const SpeedColourMap map = buildSpeedColourMap(tf, 256);
    REQUIRE(map.entries.size() == 257);
    CHECK(maxDiff(glm::dvec3(map.entries.front()), slow) < 1e-7);
    CHECK(maxDiff(glm::dvec3(map.entries.back()), fast) < 1e-7);
    for (const glm::vec4& e : map.entries) CHECK(e.w == 1.0f);
    iso::rc::gColourTestMap = map.entries;
    for (double s : {0.0, -1.0, -kInf, kNaN}) {
        CAPTURE(s);
        CHECK(lookup(map, s) == glm::dvec3(map.entries.front()));
        CHECK(glm::dvec3(iso::rc::rcSpeedColour(float(s), 256)) == glm::dvec3(map.entries.front()));
        CHECK(iso::rc::rcSpeedToMapCoord(float(s), 256) == 0.0f);
    }
    CHECK(lookup(map, kInf) == glm::dvec3(map.entries.back()));
    CHECK(glm::dvec3(iso::rc::rcSpeedColour(float(kInf), 256)) == glm::dvec3(map.entries.back()));

    // The first non-transparent sample takes everything at speed 0 even when the section starts clear.
    LocalTransferFunction late = tf;
    late.points = {{0.0, {1, 0, 0}, 0.0}, {0.5, {0, 1, 0}, 0.0}, {1.0, {0, 0, 1}, 1.0}};
    const double firstOpaque = (32 + 0.5) / n; // the first midpoint past x = 0.5
    CHECK(maxDiff(blendColour(late, 0.0), late.rgbAt(firstOpaque)) == 0.0);

    // alpha_T exactly 0 everywhere: nothing stops the ray in the section, at any speed.
    LocalTransferFunction clear = tf;
    for (TfPoint& p : clear.points) p.alpha = 0.0;
    // alpha_T exactly 1 everywhere: the first sample stops it, at any speed.
    LocalTransferFunction solid = tf;
    for (TfPoint& p : solid.points) p.alpha = 1.0;
    for (double s : {0.0, 1e-300, 1e-3, 1.0, 1e3, 1e300, kInf, kNaN, -1.0}) {
        CAPTURE(s);
        const glm::dvec3 a = blendColour(clear, s);
        const glm::dvec3 b = blendColour(solid, s);
        REQUIRE(finite(a));
        REQUIRE(finite(b));
        CHECK(maxDiff(a, clear.rgbAt(1.0)) == 0.0);
        CHECK(maxDiff(b, solid.rgbAt(0.5 / n)) == 0.0);
    }
    for (const glm::vec4& e : buildSpeedColourMap(clear, 64).entries) CHECK(finite(glm::dvec3(e)));
    for (const glm::vec4& e : buildSpeedColourMap(solid, 64).entries) CHECK(finite(glm::dvec3(e)));
}

namespace {

// The continuous volume-rendering integral through the section, for the linear ramp (alpha_T(x) = x,
// c linear from c0 to c1), written directly in the ray length l with the midpoint rule:
//   C = int_0^dl c(x(l)) sigma(x(l)) e^(-int_0^l sigma) dl + T(dl) c(1),
//   sigma(x) = -ln(1 - alpha_T(x)) / s0, x(l) = l / dl, dl = deltaV / v'.
// The optical depth up to the midpoint is the depth of the finished steps plus half of the current one.
glm::dvec3 rampIntegral(glm::dvec3 c0, glm::dvec3 c1, double deltaV, double s0, double derivative) {
    const double dl = deltaV / derivative;
    const int steps = 400000;
    const double h = dl / steps;
    glm::dvec3 colour(0.0);
    double depth = 0.0;
    for (int k = 0; k < steps; ++k) {
        const double x = (k + 0.5) / steps;
        const double sigma = -std::log(1.0 - x) / s0;
        const glm::dvec3 c = c0 + (c1 - c0) * x;
        colour += c * sigma * std::exp(-(depth + 0.5 * sigma * h)) * h;
        depth += sigma * h;
    }
    return colour + std::exp(-depth) * c1;
}

} // namespace

TEST_CASE("colour: blendColour converges to the continuous volume-rendering integral") {
    const glm::dvec3 c0(1.0, 0.9, 0.2), c1(0.2, 0.2, 0.9);
    const double deltaV = 100.0;
    const double minSpacing = 0.5;
    const double densityFactor = defaultDensityFactor(deltaV, minSpacing);
    CHECK(densityFactor == 200.0);
    const double s0 = deltaV / densityFactor; // == minSpacing
    // Slopes 10x apart: speeds 0.01, 0.1, 1 and 10.
    const std::vector<double> derivatives{2.0, 20.0, 200.0, 2000.0};
    std::vector<glm::dvec3> exact;
    for (double d : derivatives) exact.push_back(rampIntegral(c0, c1, deltaV, s0, d));
    for (std::size_t i = 0; i + 1 < exact.size(); ++i) {
        CAPTURE(derivatives[i]);
        CHECK(maxDiff(exact[i], exact[i + 1]) > 20.0 / 255.0); // the colours really tell the slopes apart
    }
    for (std::size_t i = 0; i < derivatives.size(); ++i) {
        const double speed = derivatives[i] / densityFactor;
        CAPTURE(speed);
        const double e16 = maxDiff(blendColour(rampTf(16), speed), exact[i]);
        const double e64 = maxDiff(blendColour(rampTf(64), speed), exact[i]);
        const double e256 = maxDiff(blendColour(rampTf(256), speed), exact[i]);
        MESSAGE("speed " << speed << ": |C_n - C| = " << e16 * 255.0 << " (n=16), " << e64 * 255.0
                         << " (n=64), " << e256 * 255.0 << " (n=256) /255");
        CHECK(e64 <= 6.0 / 255.0);
        CHECK(e256 < e64);
        CHECK(e64 < e16);
    }
}

TEST_CASE("colour: loadTransferFunction parses the example") {
    test::TempDir dir("colour");
    const LocalTransferFunction tf = loadTransferFunction(dir.write("example.json", kExample));
    CHECK(tf.deltaV == 100.0);
    CHECK(tf.samples == 64);
    REQUIRE(tf.points.size() == 3);
    CHECK(tf.points[1].x == 0.25);
    CHECK(tf.points[1].rgb == glm::dvec3(0.8, 0.5, 0.3));
    CHECK(tf.points[1].alpha == 0.4);
    // Linear between points, end values held.
    CHECK(tf.alphaAt(0.125) == doctest::Approx(0.2));
    CHECK(maxDiff(tf.rgbAt(0.625), glm::dvec3(0.5, 0.35, 0.6)) < 1e-12);
    CHECK(tf.alphaAt(-0.1) == 0.0);
    CHECK(tf.alphaAt(1.1) == 1.0);
    CHECK(tf.alphaAt(kNaN) == 0.0);
    CHECK(tf.rgbAt(-5.0) == glm::dvec3(1.0, 0.9, 0.2));
    CHECK(tf.rgbAt(7.0) == glm::dvec3(0.2, 0.2, 0.9));
    // Points that do not reach the ends hold their end values.
    const LocalTransferFunction inner = loadTransferFunction(
        dir.write("inner.json", R"({"points": [{"x": 0.2, "rgb": [1, 0, 0], "alpha": 0.1},
                                     {"x": 0.6, "rgb": [0, 0, 1], "alpha": 0.5}]})"));
    CHECK(inner.deltaV == 100.0); // defaults
    CHECK(inner.samples == 64);
    CHECK(inner.alphaAt(0.0) == 0.1);
    CHECK(inner.alphaAt(0.9) == 0.5);
    CHECK(inner.rgbAt(1.0) == glm::dvec3(0, 0, 1));
    // A single point is a constant function.
    const LocalTransferFunction one =
        loadTransferFunction(dir.write("one.json", R"({"delta_v": 3, "samples": 1,
            "points": [{"x": 0.5, "rgb": [0.5, 0.5, 0.5], "alpha": 0.5}]})"));
    CHECK(one.deltaV == 3.0);
    CHECK(one.alphaAt(0.0) == 0.5);
}

TEST_CASE("colour: loadTransferFunction rejects malformed files and names them") {
    test::TempDir dir("colour");
    const std::string p0 = R"({"x": 0.0, "rgb": [1, 0.9, 0.2], "alpha": 0.0})";
    const std::string p1 = R"({"x": 1.0, "rgb": [0.2, 0.2, 0.9], "alpha": 1.0})";
    auto file = [&](const std::string& head, const std::string& points) {
        return "{" + head + (head.empty() ? "" : ", ") + "\"points\": [" + points + "]}";
    };
    struct Case {
        const char* name;
        std::string text;
        const char* expect; // part of the message
    };
    const std::vector<Case> cases{
        {"bad-json", R"({"delta_v": 100, "points": [)", "bad JSON"},
        {"not-object", "[1, 2, 3]", "bad JSON"},
        {"empty", "", "bad JSON"},
        {"dv-negative", file("\"delta_v\": -1", p0 + "," + p1), "delta_v"},
        {"dv-zero", file("\"delta_v\": 0", p0 + "," + p1), "delta_v"},
        {"dv-string", file("\"delta_v\": \"100\"", p0 + "," + p1), "delta_v"},
        {"dv-huge", file("\"delta_v\": 1e999", p0 + "," + p1), ""}, // overflow: bad JSON or delta_v
        {"samples-zero", file("\"samples\": 0", p0 + "," + p1), "samples"},
        {"samples-big", file("\"samples\": 4097", p0 + "," + p1), "samples"},
        {"samples-frac", file("\"samples\": 2.5", p0 + "," + p1), "samples"},
        {"samples-neg", file("\"samples\": -3", p0 + "," + p1), "samples"},
        {"samples-string", file("\"samples\": \"64\"", p0 + "," + p1), "samples"},
        {"no-points", R"({"delta_v": 100})", "points"},
        {"points-empty", file("", ""), "points"},
        {"points-object", R"({"points": {"x": 0}})", "points"},
        {"point-not-object", file("", "3"), "points[0]"},
        {"x-missing", file("", R"({"rgb": [1, 1, 1], "alpha": 0})"), "points[0]"},
        {"x-high", file("", p0 + R"(, {"x": 1.5, "rgb": [0, 0, 0], "alpha": 1})"), "points[1]: x"},
        {"x-low", file("", R"({"x": -0.1, "rgb": [0, 0, 0], "alpha": 1})"), "points[0]: x"},
        {"x-string", file("", R"({"x": "0", "rgb": [0, 0, 0], "alpha": 1})"), "points[0]: x"},
        {"x-decreasing", file("", p1 + "," + p0), "points[1]: x"},
        {"x-repeated", file("", p0 + "," + p0), "points[1]: x"},
        {"rgb-two", file("", R"({"x": 0, "rgb": [0, 0], "alpha": 1})"), "rgb"},
        {"rgb-four", file("", R"({"x": 0, "rgb": [0, 0, 0, 0], "alpha": 1})"), "rgb"},
        {"rgb-high", file("", R"({"x": 0, "rgb": [0, 1.2, 0], "alpha": 1})"), "rgb"},
        {"rgb-negative", file("", R"({"x": 0, "rgb": [0, 0, -0.5], "alpha": 1})"), "rgb"},
        {"rgb-string", file("", R"({"x": 0, "rgb": "red", "alpha": 1})"), "rgb"},
        {"rgb-text", file("", R"({"x": 0, "rgb": [0, "1", 0], "alpha": 1})"), "rgb"},
        {"alpha-high", file("", R"({"x": 0, "rgb": [0, 0, 0], "alpha": 2})"), "alpha"},
        {"alpha-negative", file("", R"({"x": 0, "rgb": [0, 0, 0], "alpha": -0.1})"), "alpha"},
        {"alpha-null", file("", R"({"x": 0, "rgb": [0, 0, 0], "alpha": null})"), "alpha"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.name);
        const fs::path path = dir.write(std::string(c.name) + ".json", c.text);
        std::string message;
        try {
            loadTransferFunction(path);
        } catch (const InputError& e) {
            message = e.what();
        }
        CAPTURE(message);
        CHECK(message.rfind(path.string() + ": ", 0) == 0); // "<path>: <problem>"
        CHECK(message.find(c.expect) != std::string::npos);
        CHECK(message.find('\n') == std::string::npos);
    }
    const fs::path missing = dir.path / "missing.json";
    std::string message;
    try {
        loadTransferFunction(missing);
    } catch (const InputError& e) {
        message = e.what();
    }
    CHECK(message.rfind(missing.string() + ": ", 0) == 0);
}

TEST_CASE("colour: the default transfer function is valid and separates soft from sharp") {
    const LocalTransferFunction tf = defaultTransferFunction();
    CHECK_NOTHROW(validate(tf));
    CHECK(tf.deltaV > 0.0);
    CHECK(tf.samples >= 1);
    // The round trip through the file format gives the same function.
    test::TempDir dir("colour");
    std::string text = "{\"delta_v\": " + std::to_string(tf.deltaV) +
                       ", \"samples\": " + std::to_string(tf.samples) + ", \"points\": [";
    for (std::size_t i = 0; i < tf.points.size(); ++i) {
        const TfPoint& p = tf.points[i];
        char buf[256];
        std::snprintf(buf, sizeof buf, "%s{\"x\": %.17g, \"rgb\": [%.17g, %.17g, %.17g], \"alpha\": %.17g}",
                      i ? ", " : "", p.x, p.rgb.x, p.rgb.y, p.rgb.z, p.alpha);
        text += buf;
    }
    text += "]}";
    CHECK(loadTransferFunction(dir.write("default.json", text)) == tf);
    // Soft (speed 0.1) and sharp (speed 3) crossings get clearly different colours.
    CHECK(maxDiff(blendColour(tf, 0.1), blendColour(tf, 3.0)) > 60.0 / 255.0);
    // validate() rejects what the loader rejects.
    LocalTransferFunction bad = tf;
    bad.points[1].x = bad.points[0].x;
    CHECK_THROWS_AS(validate(bad), std::invalid_argument);
    bad = tf;
    bad.samples = 0;
    CHECK_THROWS_AS(validate(bad), std::invalid_argument);
    CHECK_THROWS_AS(defaultDensityFactor(100.0, 0.0), std::invalid_argument);
    CHECK_THROWS_AS(buildSpeedColourMap(tf, 0), std::invalid_argument);
}

TEST_CASE("colour: tabulate and rcTransferAt follow the transfer function") {
    test::TempDir dir("colour");
    const LocalTransferFunction tf = loadTransferFunction(dir.write("example.json", kExample));
    const int entries = 257;
    const std::vector<glm::vec4> table = tabulate(tf, entries);
    REQUIRE(table.size() == std::size_t(entries));
    CHECK(glm::length(glm::dvec3(table.front()) - tf.rgbAt(0.0)) < 1e-6); // float storage
    CHECK(table.back().w == 1.0f);
    iso::rc::gColourTestTable = table;
    // The example's points (0, 0.25, 1) fall on table entries, so the table is exact up to float.
    for (int i = 0; i <= 1000; ++i) {
        const double x = i / 1000.0;
        const glm::vec4 v = iso::rc::rcTransferAt(float(x), entries);
        CAPTURE(x);
        CHECK(maxDiff(glm::dvec3(v), tf.rgbAt(x)) < 1e-6);
        CHECK(std::abs(v.w - tf.alphaAt(x)) < 1e-6);
    }
    const glm::vec4 below = iso::rc::rcTransferAt(-0.01f, entries);
    const glm::vec4 nan = iso::rc::rcTransferAt(float(kNaN), entries);
    const glm::vec4 above = iso::rc::rcTransferAt(1.01f, entries);
    CHECK(below.w == 0.0f);
    CHECK(nan.w == 0.0f);
    CHECK(glm::dvec3(below) == glm::dvec3(table.front()));
    CHECK(glm::dvec3(nan) == glm::dvec3(table.front()));
    CHECK(above.w == 1.0f);
    CHECK(glm::dvec3(above) == glm::dvec3(table.back()));
}

TEST_CASE("colour: the speed-colour map cache rebuilds only when its inputs change") {
    SpeedColourMapCache cache;
    LocalTransferFunction tf = defaultTransferFunction();
    const SpeedColourMap& first = cache.get(tf, 256);
    CHECK(cache.rebuiltLastCall());
    CHECK(first.m == 256);
    CHECK(first.entries.size() == 257);
    cache.get(tf, 256);
    CHECK_FALSE(cache.rebuiltLastCall());
    cache.get(defaultTransferFunction(), 256); // equal content, another object
    CHECK_FALSE(cache.rebuiltLastCall());
    CHECK(cache.get(tf, 1024).m == 1024);
    CHECK(cache.rebuiltLastCall());
    cache.get(tf, 1024);
    CHECK_FALSE(cache.rebuiltLastCall());
    tf.points[1].rgb.y += 0.01;
    cache.get(tf, 1024);
    CHECK(cache.rebuiltLastCall());
    tf.samples = 32;
    cache.get(tf, 1024);
    CHECK(cache.rebuiltLastCall());
    tf.deltaV = 50.0;
    cache.get(tf, 1024);
    CHECK(cache.rebuiltLastCall());
    // The cached map equals a fresh build.
    const SpeedColourMap fresh = buildSpeedColourMap(tf, 1024);
    CHECK(cache.get(tf, 1024).entries == fresh.entries);
    CHECK_FALSE(cache.rebuiltLastCall());
    // A failed build keeps the previous map.
    CHECK_THROWS(cache.get(tf, 0));
    CHECK_FALSE(cache.rebuiltLastCall());
    cache.get(tf, 1024);
    CHECK_FALSE(cache.rebuiltLastCall());
}

TEST_CASE("colour: rcCorrectOpacity matches 1 - (1 - alpha)^r") {
    for (float alpha : {0.0f, 1.0f, 0.5f, 1e-6f, 0.003f, 0.999f}) {
        for (float r : {1.0f, 2.0f, 0.5f, 0.01f, 100.0f}) {
            CAPTURE(alpha);
            CAPTURE(r);
            const double expected = 1.0 - std::pow(1.0 - double(alpha), double(r));
            const float got = iso::rc::rcCorrectOpacity(alpha, r);
            // Relative accuracy holds for small opacities too (the series branches).
            CHECK(std::abs(got - expected) <= 1e-6 * std::max(expected, 1e-3));
        }
    }
    CHECK(iso::rc::rcCorrectOpacity(1.0f, 1e-9f) == 1.0f);
    CHECK(iso::rc::rcCorrectOpacity(0.0f, 1e9f) == 0.0f);
    CHECK(iso::rc::rcCorrectOpacity(0.5f, 0.0f) == 0.0f);
    CHECK(iso::rc::rcCorrectOpacity(0.5f, float(kInf)) == 1.0f);
    CHECK(iso::rc::rcCorrectOpacity(float(kNaN), 1.0f) == 0.0f);
    CHECK(iso::rc::rcCorrectOpacity(0.5f, float(kNaN)) == 0.0f);
    CHECK(iso::rc::rcCorrectOpacity(2.0f, 1.0f) == 1.0f);
}
