// CEIR's colour model (engine/colour and shaders/shared/ceir.h): the speed-colour map against a direct
// evaluation, the shader's lookup against the CPU's, the blend against an independent evaluation of the
// continuous volume-rendering integral, and the transfer-function file format.
#include "colour/speed_colour_map.hpp"
#include "colour/transfer_function.hpp"
#include "io/volume.hpp"

#include <doctest/doctest.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
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
inline glm::vec4 rcSpeedColourEntry(int j) { return gColourTestMap.at(std::size_t(j)); }
inline glm::vec4 rcTransferEntry(int k) { return gColourTestTable.at(std::size_t(k)); }
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

bool finite(glm::dvec3 c) { return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z); }

// count speeds log-spaced over [1e-3, 1e3].
std::vector<double> logSpeeds(int count) {
    std::vector<double> s(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i) s[std::size_t(i)] = std::pow(10.0, -3.0 + 6.0 * i / (count - 1));
    return s;
}

double worstMapError(const LocalTransferFunction& tf, int m) {
    const SpeedColourMap map = buildSpeedColourMap(tf, m);
    double worst = 0.0;
    for (double s : logSpeeds(2001)) worst = std::max(worst, maxDiff(lookup(map, s), blendColour(tf, s)));
    return worst;
}

struct TempDir {
    fs::path path;
    TempDir() {
        std::random_device rd;
        path = fs::temp_directory_path() /
               ("isoscope-colour-" + std::to_string(rd()) + "-" + std::to_string(rd()));
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    fs::path write(const std::string& name, const std::string& text) const {
        const fs::path p = path / name;
        std::ofstream(p, std::ios::binary) << text;
        return p;
    }
};

const char* const kExample = R"({"delta_v": 100.0, "samples": 64, "points": [
    {"x": 0.0, "rgb": [1, 0.9, 0.2], "alpha": 0.0},
    {"x": 0.25, "rgb": [0.8, 0.5, 0.3], "alpha": 0.4},
    {"x": 1.0, "rgb": [0.2, 0.2, 0.9], "alpha": 1.0}]})";

} // namespace

TEST_CASE("colour: the speed-colour map matches blendColour and its error shrinks with m") {
    for (const LocalTransferFunction& tf : {rampTf(), defaultTransferFunction()}) {
        const double e256 = worstMapError(tf, 256);
        const double e1024 = worstMapError(tf, 1024);
        MESSAGE("map error m=256: " << e256 * 255.0 << "/255, m=1024: " << e1024 * 255.0 << "/255");
    }
}
TEST_CASE("colour: scratch") {
    for (const LocalTransferFunction& tf : {rampTf(), defaultTransferFunction()}) {
        for (int m : {256, 1024, 4096}) {
            const SpeedColourMap map = buildSpeedColourMap(tf, m);
            double wIn = 0, wTail = 0, sIn = 0, sTail = 0;
            for (double s : logSpeeds(4001)) {
                double e = maxDiff(lookup(map, s), blendColour(tf, s));
                bool tail = speedToMapCoord(s, m) >= m - 1;
                if (tail) { if (e > wTail) { wTail = e; sTail = s; } }
                else if (e > wIn) { wIn = e; sIn = s; }
            }
            MESSAGE("m=" << m << " inner " << wIn * 255 << " at " << sIn << " tail " << wTail * 255 << " at " << sTail);
        }
        for (double s : {0.0, 0.001, 0.01, 0.1, 0.3, 1.0, 3.0, 10.0, 100.0}) {
            auto c = blendColour(tf, s);
            MESSAGE("s=" << s << " C=" << c.x * 255 << "," << c.y * 255 << "," << c.z * 255);
        }
    }
}
