// Golden images: a regression guard, never the proof of correctness (the oracle tests are).
#pragma once

#include "io/image_write.hpp"
#include "render/renderer.hpp"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace iso::test {

// Golden-image regression guard for any name: tests/golden/<name>.png with its
// tolerances in tests/golden/<name>.json. ISOSCOPE_UPDATE_GOLDEN=1 rewrites the image (and writes the
// tolerance file with the default tolerances if there is none yet, so hand-tuned ones survive).
inline void checkGolden(const std::string& name, const std::string& what, const Frame& f) {
    const std::filesystem::path src = ISOSCOPE_SOURCE_DIR;
    const auto golden = src / "tests/golden" / (name + ".png");
    const auto tolPath = src / "tests/golden" / (name + ".json");
    const std::vector<uint8_t> got = encodeSrgb8(f.rgba);
    if (std::getenv("ISOSCOPE_UPDATE_GOLDEN")) {
        writePng(golden, f.width, f.height, got);
        if (!std::filesystem::exists(tolPath)) {
            nlohmann::ordered_json j;
            j["image"] = name + ".png";
            j["what"] = what;
            j["max_abs_diff"] = 6;
            j["max_failing_pixels_fraction"] = 0.003;
            std::ofstream(tolPath) << j.dump(2) << "\n";
        }
    }
    std::ifstream tolFile(tolPath);
    REQUIRE(tolFile.good());
    const auto tol = nlohmann::json::parse(tolFile);
    const int maxAbsDiff = tol.at("max_abs_diff").get<int>();
    const double maxFailing = tol.at("max_failing_pixels_fraction").get<double>();
    int w = 0, h = 0;
    const std::vector<uint8_t> want = readPng(golden, w, h);
    REQUIRE(w == f.width);
    REQUIRE(h == f.height);
    int worst = 0;
    std::size_t failing = 0;
    std::vector<uint8_t> diff(want.size(), 255);
    for (std::size_t p = 0; p < want.size() / 4; ++p) {
        int d = 0;
        for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(got[4 * p + c]) - int(want[4 * p + c])));
        worst = std::max(worst, d);
        failing += d > maxAbsDiff;
        for (int c = 0; c < 3; ++c) diff[4 * p + c] = uint8_t(std::min(255, d * 8));
    }
    const double fraction = double(failing) / double(want.size() / 4);
    MESSAGE(name << ": worst difference " << worst << ", failing pixels " << failing);
    if (fraction > maxFailing) {
        const auto out = std::filesystem::path(ISOSCOPE_BINARY_DIR) / ("golden-diff-" + name + ".png");
        writePng(out, f.width, f.height, diff);
        MESSAGE("golden mismatch: diff image " << out.string());
    }
    CHECK(fraction <= maxFailing);
}

} // namespace iso::test
