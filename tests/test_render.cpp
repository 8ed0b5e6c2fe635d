// The Vulkan isoSurface pass against the float64 oracle on analytic volumes (lavapipe in CI), the
// bundled scan against a golden image, and the render graph's own behaviour.
#include "golden.hpp"
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
    test::checkGolden("headsq_skin_128",
                      "data/headsq_quarter.nhdr, iso 500, data/headsq_quarter.camera.json, 128x128, mono", f);
    CHECK(test::gpu().validationMessages() == 0);
}
