// The Vulkan isoSurface pass against the float64 oracle on analytic volumes (lavapipe in CI), the
// bundled scan against a golden image, and the render graph's own behaviour.
#include "gpu_fixture.hpp"

#include "io/image_write.hpp"
#include "oracle/analytic.hpp"
#include "oracle/metrics.hpp"
#include "oracle/oracle.hpp"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

using namespace iso;

namespace {

struct Case {
    const char* name;
    Camera camera;
};

oracle::Metrics renderAndCompare(const Volume& vol, double iso, const Camera& cam, int w, int h,
                                 std::optional<std::array<double, 6>> crop = std::nullopt) {
    Renderer renderer(test::gpu());
    renderer.setVolume(vol);
    RenderSettings s;
    s.width = w;
    s.height = h;
    s.iso = iso;
    s.camera = cam;
    s.crop = crop;
    Frame f = renderer.render(s, {true, true, true});
    oracle::Options opt;
    opt.iso = iso;
    opt.crop = crop;
    oracle::Image ref = oracle::render(vol, cam, w, h, opt);
    std::vector<uint64_t> ids(f.voxelIds.size());
    for (size_t i = 0; i < ids.size(); ++i)
        ids[i] = f.voxelIds[i] == 0xFFFFFFFFu ? UINT64_MAX : f.voxelIds[i];
    oracle::Metrics m = oracle::compare(ref, vol, f.depth, ids);
    for (float v : f.rgba) m.nonFinite += std::isfinite(v) ? 0 : 1;
    return m;
}

// The foundation's targets: hit/miss and id mismatch <= 1e-3 of pixels, depth p99 <= 1e-3 voxel.
void checkTargets(const oracle::Metrics& m, const std::string& what) {
    MESSAGE(what << ": " << oracle::format(m));
    CHECK(m.bothHit > 100); // the view really sees the surface
    CHECK(m.hitMissMismatch <= 1e-3);
    CHECK(m.depthP99 <= 1e-3);
    CHECK(m.idMismatch <= 1e-3);
    CHECK(m.nonFinite == 0);
}

std::vector<Camera> views(const Volume& vol) {
    return {frameVolume(vol, 64, 64), test::orbitCamera(vol, 35.0, 25.0),
            test::orbitCamera(vol, -120.0, -40.0)};
}

} // namespace

TEST_CASE("gpu: sphere distance field matches the oracle") {
    auto scene = analytic::sphereDistance(24, 8.0);
    for (const auto& cam : views(scene.vol))
        checkTargets(renderAndCompare(scene.vol, scene.iso, cam, 64, 64), "sphere");
    CHECK(test::gpu().validationMessages() == 0);
}

TEST_CASE("gpu: Marschner-Lobb matches the oracle") {
    auto scene = analytic::marschnerLobb(41);
    for (const auto& cam : views(scene.vol))
        checkTargets(renderAndCompare(scene.vol, scene.iso, cam, 64, 64), "ML");
    CHECK(test::gpu().validationMessages() == 0);
}

TEST_CASE("gpu: anisotropic spacing, rotated directions and an origin match the oracle") {
    auto scene = analytic::sphereAnisotropic(24, 9.0);
    for (const auto& cam : views(scene.vol))
        checkTargets(renderAndCompare(scene.vol, scene.iso, cam, 64, 64), "anisotropic");
    CHECK(test::gpu().validationMessages() == 0);
}

TEST_CASE("gpu: a u16 scan matches the oracle") {
    auto scene = analytic::sphereU16(24, 8.0);
    for (const auto& cam : views(scene.vol))
        checkTargets(renderAndCompare(scene.vol, scene.iso, cam, 64, 64), "u16");
    CHECK(test::gpu().validationMessages() == 0);
}

TEST_CASE("gpu: an orthographic camera matches the oracle") {
    auto scene = analytic::marschnerLobb(41);
    Camera cam = test::orbitCamera(scene.vol, 20.0, 30.0);
    cam.orthographic = true;
    cam.height = 2.4;
    checkTargets(renderAndCompare(scene.vol, scene.iso, cam, 64, 64), "orthographic");
    CHECK(test::gpu().validationMessages() == 0);
}

TEST_CASE("gpu: the bundled head matches its golden image") {
    const std::filesystem::path src = ISOSCOPE_SOURCE_DIR;
    Volume vol = loadVolume(src / "data/headsq_quarter.nhdr");
    Renderer renderer(test::gpu());
    renderer.setVolume(vol);
    RenderSettings s;
    s.width = s.height = 128;
    s.iso = 500.0;
    s.camera = loadCamera(src / "data/headsq_quarter.camera.json");
    Frame f = renderer.render(s);
    std::vector<uint8_t> got = encodeSrgb8(f.rgba);

    const auto golden = src / "tests/golden/headsq_skin_128.png";
    if (std::getenv("ISOSCOPE_UPDATE_GOLDEN")) writePng(golden, 128, 128, got);
    // Tolerances live beside the image: lavapipe and GPUs round differently at silhouettes.
    std::ifstream tolFile(src / "tests/golden/headsq_skin_128.json");
    REQUIRE(tolFile.good());
    auto tol = nlohmann::json::parse(tolFile);
    const int maxAbsDiff = tol.at("max_abs_diff").get<int>();
    const double maxFailing = tol.at("max_failing_pixels_fraction").get<double>();
    int w = 0, h = 0;
    std::vector<uint8_t> want = readPng(golden, w, h);
    REQUIRE(w == 128);
    REQUIRE(h == 128);
    int worst = 0;
    size_t failing = 0;
    std::vector<uint8_t> diff(want.size(), 255);
    for (size_t p = 0; p < want.size() / 4; ++p) {
        int d = 0;
        for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(got[4 * p + c]) - int(want[4 * p + c])));
        worst = std::max(worst, d);
        failing += d > maxAbsDiff;
        for (int c = 0; c < 3; ++c) diff[4 * p + c] = uint8_t(std::min(255, d * 8));
    }
    double fraction = double(failing) / double(want.size() / 4);
    if (fraction > maxFailing) {
        auto out = std::filesystem::path(ISOSCOPE_BINARY_DIR) / "golden-diff-headsq_skin_128.png";
        writePng(out, 128, 128, diff);
        MESSAGE("golden mismatch: worst difference " << worst << ", failing pixels " << failing
                                                     << "; diff image " << out.string());
    }
    CHECK(fraction <= maxFailing);
    CHECK(test::gpu().validationMessages() == 0);
}
