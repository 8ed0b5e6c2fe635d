// The float64 oracle, the camera it shares with the renderer, the analytic scenes and the metrics.
#include "io/volume.hpp"
#include "oracle/analytic.hpp"
#include "oracle/metrics.hpp"
#include "oracle/oracle.hpp"
#include "scene/camera.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <utility>

using namespace iso;

namespace {

constexpr double kEps = 1e-9;

glm::dvec3 unit(double x, double y, double z) {
    return glm::normalize(glm::dvec3(x, y, z));
}

oracle::Hit traceIso(const Volume& v, const Ray& r, double iso, int skip = 0) {
    oracle::Options o;
    o.iso = iso;
    o.skipCrossings = skip;
    return oracle::trace(v, r, o);
}

void setF32(Volume& v, uint32_t i, uint32_t j, uint32_t k, float x) {
    std::memcpy(v.data.data() + v.index(i, j, k) * sizeof(float), &x, sizeof x);
}

// A file in a fresh temporary directory, removed with it.
struct TempFile {
    std::filesystem::path dir, path;
    TempFile(const std::string& name, const std::string& text) {
        static int counter = 0;
        dir = std::filesystem::temp_directory_path() /
              ("isoscope_oracle_" + std::to_string(std::random_device{}()) + "_" + std::to_string(counter++));
        std::filesystem::create_directories(dir);
        path = dir / name;
        std::ofstream(path) << text;
    }
    ~TempFile() { std::filesystem::remove_all(dir); }
};

std::string loadError(const std::filesystem::path& p) {
    try {
        loadCamera(p);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST_CASE("oracle: primaryRay centre pixel of a perspective camera points at the target") {
    Camera cam;
    cam.eye = {10, -40, 5};
    cam.target = {1, 2, 3};
    cam.up = {0, 0, 1};
    cam.fovyDeg = 40;
    const int w = 101, h = 61;
    const Ray c = primaryRay(cam, w, h, 50, 30);
    const glm::dvec3 fwd = glm::normalize(cam.target - cam.eye);
    CHECK(glm::length(c.origin - cam.eye) == 0.0);
    CHECK(glm::length(c.dir - fwd) < 1e-12);

    // Off-centre pixels follow the u/v formula: x to the right, y down.
    const glm::dvec3 right = glm::normalize(glm::cross(fwd, cam.up)), up = glm::cross(right, fwd);
    const double tanHalf = std::tan(glm::radians(40.0) / 2), aspect = double(w) / h;
    const Ray r = primaryRay(cam, w, h, 0, 0);
    CHECK(std::abs(glm::length(r.dir) - 1.0) < 1e-12);
    const double f = glm::dot(r.dir, fwd);
    CHECK(glm::dot(r.dir, right) / f == doctest::Approx((0.5 / w * 2 - 1) * tanHalf * aspect).epsilon(1e-12));
    CHECK(glm::dot(r.dir, up) / f == doctest::Approx((1 - 0.5 / h * 2) * tanHalf).epsilon(1e-12));
}

TEST_CASE("oracle: orthographic rays are parallel and their origins lie on the eye plane") {
    Camera cam;
    cam.eye = {3, -50, 2};
    cam.target = {3, 0, 2};
    cam.up = {0, 0, 1};
    cam.orthographic = true;
    cam.height = 20;
    const int w = 40, h = 30;
    for (int y = 0; y < h; y += 7)
        for (int x = 0; x < w; x += 9) {
            const Ray r = primaryRay(cam, w, h, x, y);
            CHECK(glm::length(r.dir - glm::dvec3(0, 1, 0)) < 1e-15);
            CHECK(std::abs(glm::dot(r.origin - cam.eye, r.dir)) < 1e-12);
        }
    // Top-left pixel centre: left and up of the eye by almost half the visible width and height.
    const Ray tl = primaryRay(cam, w, h, 0, 0);
    CHECK(tl.origin.x == doctest::Approx(3 - (1 - 1.0 / w) * 10 * w / h));
    CHECK(tl.origin.z == doctest::Approx(2 + (1 - 1.0 / h) * 10));
}

TEST_CASE("oracle: loadCamera parses both forms") {
    TempFile p("persp.json", R"({"eye":[1,2,3],"target":[0,0,0],"up":[0,0,1],"fovy_deg":45})");
    const Camera c = loadCamera(p.path);
    CHECK(c.eye == glm::dvec3(1, 2, 3));
    CHECK(c.target == glm::dvec3(0));
    CHECK(c.up == glm::dvec3(0, 0, 1));
    CHECK(c.fovyDeg == 45.0);
    CHECK_FALSE(c.orthographic);

    TempFile o("ortho.json",
               R"({"eye":[0,-9,0],"target":[0,0,0],"up":[0,0,1],"projection":"orthographic","height":12.5})");
    const Camera d = loadCamera(o.path);
    CHECK(d.orthographic);
    CHECK(d.height == 12.5);
}

TEST_CASE("oracle: loadCamera rejects bad cameras with the file name in the message") {
    const char* bad[] = {
        R"({"eye":[1,2,3],"target":[0,0,0],"up":[0,0,1],"fovy_deg":45)",    // bad JSON
        R"({"eye":[1,2,3],"target":[0,0,0],"fovy_deg":45})",                // no up
        R"({"eye":[1,2],"target":[0,0,0],"up":[0,0,1],"fovy_deg":45})",     // 2 numbers
        R"({"eye":[1,"a",3],"target":[0,0,0],"up":[0,0,1],"fovy_deg":45})", // not a number
        R"({"eye":[1,2,3],"target":[1,2,3],"up":[0,0,1],"fovy_deg":45})",   // eye == target
        R"({"eye":[0,0,5],"target":[0,0,0],"up":[0,0,1],"fovy_deg":45})",   // up parallel
        R"({"eye":[1,2,3],"target":[0,0,0],"up":[0,0,0],"fovy_deg":45})",   // up zero
        R"({"eye":[1,2,3],"target":[0,0,0],"up":[0,0,1],"fovy_deg":0})",    // fovy 0
        R"({"eye":[1,2,3],"target":[0,0,0],"up":[0,0,1],"fovy_deg":180})",  // fovy 180
        R"({"eye":[1,2,3],"target":[0,0,0],"up":[0,0,1]})",                 // no fovy
        R"({"eye":[1,2,3],"target":[0,0,0],"up":[0,0,1],"projection":"orthographic","height":0})",
        R"({"eye":[1,2,3],"target":[0,0,0],"up":[0,0,1],"projection":"orthographic","height":-2})",
        R"({"eye":[1,2,3],"target":[0,0,0],"up":[0,0,1],"projection":"orthographic"})", // no height
        R"({"eye":[1,2,3],"target":[0,0,0],"up":[0,0,1],"projection":"fisheye","fovy_deg":45})",
        R"([1,2,3])",
    };
    for (const char* text : bad) {
        TempFile f("bad_camera.json", text);
        const std::string msg = loadError(f.path);
        INFO(text, " -> ", msg);
        CHECK(msg.rfind(f.path.string() + ": ", 0) == 0);
    }
    const std::string missing = loadError("/nonexistent/cam.json");
    CHECK(missing.rfind("/nonexistent/cam.json: ", 0) == 0);
}

TEST_CASE("oracle: frameVolume looks at the volume centre from anterior and fits it") {
    const auto s = analytic::sphereAnisotropic(20, 5.0);
    for (auto [w, h] : {std::pair{200, 100}, std::pair{100, 200}}) {
        const Camera cam = frameVolume(s.vol, w, h);
        CHECK(glm::length(cam.target - s.centre) < 1e-9);
        const glm::dvec3 back = cam.eye - cam.target;
        CHECK(std::abs(back.x) + std::abs(back.z) < 1e-12);
        CHECK(back.y < 0.0);
        CHECK(cam.up == glm::dvec3(0, 0, 1));
        CHECK(cam.fovyDeg == 30.0);
        // Every corner projects inside the image.
        const glm::dvec3 f = glm::normalize(-back), r = glm::normalize(glm::cross(f, cam.up)),
                         u = glm::cross(r, f);
        const double tanHalf = std::tan(glm::radians(15.0));
        for (int c = 0; c < 8; ++c) {
            const glm::dvec3 v = s.vol.worldOf(glm::dvec3(c & 1, c >> 1 & 1, c >> 2 & 1) * 19.0) - cam.eye;
            CHECK(std::abs(glm::dot(v, r) / glm::dot(v, f)) < tanHalf * w / h);
            CHECK(std::abs(glm::dot(v, u) / glm::dot(v, f)) < tanHalf);
        }
    }
}

TEST_CASE("oracle: linear ramp f = x hits at the exact analytic t") {
    const Volume v = analytic::linearRamp({24, 16, 12}, {1, 0, 0});
    const double iso = 10.25;

    SUBCASE("axis-aligned") {
        const auto h = traceIso(v, {{-5, 7.3, 4.6}, {1, 0, 0}}, iso);
        REQUIRE(h.hit);
        CHECK(std::abs(h.t - 15.25) < kEps);
        CHECK(std::abs(h.value - iso) < kEps);
        CHECK(glm::length(h.gradient - glm::dvec3(1, 0, 0)) < kEps);
        CHECK(glm::length(h.worldPos - glm::dvec3(10.25, 7.3, 4.6)) < kEps);
    }
    SUBCASE("oblique") {
        const Ray r{{-3, 2, 9}, unit(1, 0.3, -0.2)};
        const auto h = traceIso(v, r, iso);
        REQUIRE(h.hit);
        CHECK(std::abs(h.t - 13.25 / r.dir.x) < kEps);
    }
    SUBCASE("oblique from the far side, entering inside") {
        // The box entry (x = 23) is already inside; the surface is where f drops below iso.
        const Ray r{{30, 8, 6}, unit(-1, 0.1, 0.05)};
        const auto h = traceIso(v, r, iso);
        REQUIRE(h.hit);
        CHECK(std::abs(h.t - 19.75 / -r.dir.x) < kEps);
    }
    SUBCASE("many random rays against a skewed ramp") {
        // f = 0.5 i - 0.25 j + 0.75 k is exact in floats and linear in index space, hence everywhere.
        const auto g = glm::dvec3(0.5, -0.25, 0.75);
        Volume w = analytic::linearRamp({20, 16, 12}, g);
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> U(-1, 1);
        int hits = 0;
        for (int n = 0; n < 300; ++n) {
            // Aim near the box from all around, so that most rays pass through it.
            const glm::dvec3 origin = glm::dvec3(10, 8, 6) + 25.0 * glm::dvec3(U(rng), U(rng), U(rng));
            const glm::dvec3 aim =
                glm::dvec3(10, 8, 6) + glm::dvec3(11, 9, 7) * glm::dvec3(U(rng), U(rng), U(rng));
            const Ray r{origin, glm::normalize(aim - origin)};
            const double isoR = 6.0 + 2.0 * U(rng);
            // A linear f crosses iso once along the whole line; the oracle must report it iff it is
            // in front of the origin and inside the box.
            const double tA = (isoR - glm::dot(g, r.origin)) / glm::dot(g, r.dir);
            const glm::dvec3 p = r.origin + tA * r.dir;
            const double margin = std::min({p.x, p.y, p.z, 19 - p.x, 15 - p.y, 11 - p.z});
            if (std::abs(margin) < 1e-6 || std::abs(tA) < 1e-6) continue;
            const auto h = traceIso(w, r, isoR);
            INFO("ray ", n);
            CHECK(h.hit == (tA > 0 && margin > 0));
            if (h.hit) {
                ++hits;
                CHECK(std::abs(h.t - tA) < kEps);
            }
        }
        CHECK(hits > 50);
    }
}

TEST_CASE("oracle: anisotropic rotated geometry maps index and world space consistently") {
    // Integer-valued f = i + 2j - k is exact in floats; in world space it is linear as well.
    Volume v = analytic::sphereAnisotropic(16, 5.0).vol;
    for (uint32_t k = 0; k < 16; ++k)
        for (uint32_t j = 0; j < 16; ++j)
            for (uint32_t i = 0; i < 16; ++i) setF32(v, i, j, k, float(i + 2.0 * j - k));
    const double iso = 17.5;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> U(0.5, 14.5);
    for (int n = 0; n < 20; ++n) {
        const glm::dvec3 aim = v.worldOf({U(rng), U(rng), U(rng)});
        const glm::dvec3 eye = aim + 80.0 * unit(U(rng) - 7.5, U(rng) - 7.5, U(rng) - 7.5);
        const Ray r{eye, glm::normalize(aim - eye)};
        const auto h = traceIso(v, r, iso);
        if (!h.hit) continue;
        const glm::dvec3 ijk = h.indexPos;
        CHECK(std::abs(ijk.x + 2 * ijk.y - ijk.z - iso) < kEps);
        CHECK(glm::length(v.worldOf(ijk) - h.worldPos) < kEps);
        CHECK(std::abs(glm::length(h.worldPos - r.origin) - h.t) < kEps);
        // The world gradient reproduces index-space differences along each grid axis.
        const glm::dvec3 G(1, 2, -1);
        for (int a = 0; a < 3; ++a) {
            glm::dvec3 e(0.0);
            e[a] = 1.0;
            CHECK(glm::dot(h.gradient, v.worldOf(ijk + e) - v.worldOf(ijk)) == doctest::Approx(G[a]));
        }
    }
}

TEST_CASE("oracle: sphere distance fields agree with the analytic sphere for central rays") {
    struct Case {
        std::string name;
        analytic::SphereScene s;
    };
    Case cases[] = {{"f32", analytic::sphereDistance(48, 16.0)},
                    {"anisotropic", analytic::sphereAnisotropic(80, 28.0)},
                    {"u16", analytic::sphereU16(48, 16.0)},
                    {"spacing", analytic::sphereDistance(40, 17.0, {1.5, 1.2, 1.0})}};
    for (const Case& c : cases) {
        INFO(c.name);
        const auto& s = c.s;
        const double voxel = std::min({s.vol.spacing.x, s.vol.spacing.y, s.vol.spacing.z});
        const int w = 48, h = 40;
        const Camera cam = frameVolume(s.vol, w, h);
        oracle::Options opt;
        opt.iso = s.iso;
        const oracle::Image img = oracle::render(s.vol, cam, w, h, opt);
        REQUIRE(img.hits.size() == size_t(w * h));
        int central = 0;
        double worst = 0.0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const Ray r = primaryRay(cam, w, h, x, y);
                const auto& hit = img.hits[size_t(y * w + x)];
                // render is trace per pixel
                const auto again = oracle::trace(s.vol, r, opt);
                CHECK(again.hit == hit.hit);
                if (hit.hit) CHECK(again.t == hit.t);
                const double miss = glm::length(glm::cross(s.centre - r.origin, r.dir));
                if (miss > 0.7 * s.radius) continue;
                ++central;
                const double tA = analytic::analyticSphereT(r, s.centre, s.radius);
                REQUIRE(hit.hit);
                worst = std::max(worst, std::abs(hit.t - tA) / voxel);
                CHECK(std::abs(hit.value - s.iso) < 1e-9 * std::max(1.0, s.iso));
            }
        CHECK(central > 30);
        CHECK(worst < 0.05);
    }
}

TEST_CASE("oracle: a grazing ray just outside the sphere misses") {
    const auto s = analytic::sphereDistance(48, 16.0);
    const glm::dvec3 side(0, 0, 1);
    // The interpolant of a concave distance field never exceeds it, so outside the sphere stays outside.
    CHECK_FALSE(
        traceIso(s.vol, {s.centre + (s.radius + 0.02) * side - glm::dvec3(40, 0, 0), {1, 0, 0}}, s.iso).hit);
    CHECK_FALSE(traceIso(s.vol,
                         {s.centre + (s.radius + 0.02) * unit(0, 1, 1) - glm::dvec3(40, 0, 0), {1, 0, 0}},
                         s.iso)
                    .hit);
    CHECK(traceIso(s.vol, {s.centre + (s.radius - 0.5) * side - glm::dvec3(40, 0, 0), {1, 0, 0}}, s.iso).hit);
}

TEST_CASE("oracle: a ray starting inside the box starts at t = 0") {
    const Volume v = analytic::linearRamp({24, 16, 12}, {1, 0, 0});
    CHECK(traceIso(v, {{3, 5, 5}, {1, 0, 0}}, 10.25).t == doctest::Approx(7.25).epsilon(1e-12));
    CHECK(traceIso(v, {{12, 5, 5}, {-1, 0, 0}}, 10.25).t == doctest::Approx(1.75).epsilon(1e-12));
    // Starting inside the surface is not a crossing, and the crossing behind the origin does not count.
    CHECK_FALSE(traceIso(v, {{12, 5, 5}, {1, 0, 0}}, 10.25).hit);
    CHECK_FALSE(traceIso(v, {{11, 5, 5}, {1, 0, 0}}, 10.25).hit);
}

TEST_CASE("oracle: a ray parallel to a face lying exactly on it") {
    const Volume v = analytic::linearRamp({24, 16, 12}, {1, 0, 0});
    auto h = traceIso(v, {{-5, 0, 3}, {1, 0, 0}}, 10.25);
    REQUIRE(h.hit);
    CHECK(std::abs(h.t - 15.25) < kEps);
    h = traceIso(v, {{-5, 15, 11}, {1, 0, 0}}, 10.25); // on the top far edge
    REQUIRE(h.hit);
    CHECK(std::abs(h.t - 15.25) < kEps);
    CHECK(h.cell == std::array<uint32_t, 3>{10, 14, 10});
    const Ray inPlane{{-5, 0, 0.5}, unit(1, 0, 0.3)};
    h = traceIso(v, inPlane, 10.25);
    REQUIRE(h.hit);
    CHECK(std::abs(h.t - 15.25 / inPlane.dir.x) < kEps);
    CHECK_FALSE(traceIso(v, {{-5, -1e-9, 3}, {1, 0, 0}}, 10.25).hit);
    CHECK_FALSE(traceIso(v, {{-5, 15 + 1e-9, 3}, {1, 0, 0}}, 10.25).hit);
}

TEST_CASE("oracle: a cell with a NaN corner holds no surface while its neighbours do") {
    Volume v = analytic::linearRamp({24, 16, 12}, {1, 0, 0});
    setF32(v, 10, 5, 5, std::numeric_limits<float>::quiet_NaN()); // poisons cells i 9..10, j 4..5, k 4..5
    CHECK_FALSE(traceIso(v, {{-5, 4.5, 4.5}, {1, 0, 0}}, 10.25).hit);
    CHECK_FALSE(traceIso(v, {{-5, 5.5, 5.0}, {1, 0, 0}}, 10.25).hit);
    auto h = traceIso(v, {{-5, 6.5, 4.5}, {1, 0, 0}}, 10.25);
    REQUIRE(h.hit);
    CHECK(std::abs(h.t - 15.25) < kEps);
    h = traceIso(v, {{-5, 4.5, 4.5}, {1, 0, 0}}, 5.5); // same row, a crossing in front of the bad cells
    REQUIRE(h.hit);
    CHECK(std::abs(h.t - 10.5) < kEps);
}

TEST_CASE("oracle: skipCrossings reaches the second and third shells in order") {
    const auto s = analytic::nestedShells(64, {8, 16, 24});
    const Ray r{s.centre + glm::dvec3(0.3, -40, 0.2), {0, 1, 0}};
    double expect[] = {40 - 24, 40 - 16, 40 - 8, 40 + 8, 40 + 16, 40 + 24};
    double last = -1.0;
    for (int skip = 0; skip < 6; ++skip) {
        const auto h = traceIso(s.vol, r, s.iso, skip);
        INFO("skip ", skip);
        REQUIRE(h.hit);
        CHECK(h.t > last);
        CHECK(std::abs(h.t - expect[skip]) < 0.1);
        last = h.t;
    }
    CHECK_FALSE(traceIso(s.vol, r, s.iso, 6).hit);
}

TEST_CASE("oracle: crop cuts off the front shell") {
    const auto s = analytic::nestedShells(64, {8, 16, 24});
    const Ray r{s.centre + glm::dvec3(0.3, -40, 0.2), {0, 1, 0}};
    oracle::Options opt;
    opt.iso = s.iso;
    opt.crop = std::array<double, 6>{0, s.centre.y - 20, 0, 63, 63, 63}; // starts between outer and middle
    auto h = oracle::trace(s.vol, r, opt);
    REQUIRE(h.hit);
    CHECK(std::abs(h.t - (40 - 16)) < 0.1);
    CHECK(h.indexPos.y >= s.centre.y - 20);
    opt.crop = std::array<double, 6>{0, 0, 0, s.centre.x - 1, 63, 63}; // the ray is outside the crop
    CHECK_FALSE(oracle::trace(s.vol, r, opt).hit);
}

TEST_CASE("oracle: cell ids follow i + nx (j + ny k) and a face root belongs to the cell the ray leaves") {
    const Volume v = analytic::linearRamp({24, 16, 12}, {1, 0, 0});
    auto h = traceIso(v, {{-5, 7.3, 4.6}, {1, 0, 0}}, 10.25);
    REQUIRE(h.hit);
    CHECK(h.cell == std::array<uint32_t, 3>{10, 7, 4});
    CHECK(h.cellId == 10 + 24 * (7 + 16 * 4));
    h = traceIso(v, {{-5, 7.3, 4.6}, {1, 0, 0}}, 10.0);
    REQUIRE(h.hit);
    CHECK(h.t == doctest::Approx(15.0).epsilon(1e-12));
    CHECK(h.cell[0] == 9);
    h = traceIso(v, {{30, 7.3, 4.6}, {-1, 0, 0}}, 10.0);
    REQUIRE(h.hit);
    CHECK(h.t == doctest::Approx(20.0).epsilon(1e-12));
    CHECK(h.cell[0] == 10);
    // A root on a face counts once: nothing behind it.
    CHECK_FALSE(traceIso(v, {{-5, 7.3, 4.6}, {1, 0, 0}}, 10.0, 1).hit);
}

TEST_CASE("oracle: flat cell with all corners at iso hits at the cell entry") {
    SUBCASE("constant volume: the box entry") {
        Volume v = analytic::linearRamp({6, 5, 4}, {0, 0, 0});
        for (uint32_t i = 0; i < 6 * 5 * 4; ++i) setF32(v, i, 0, 0, 3.0f);
        const auto h = traceIso(v, {{-2, 2.5, 1.5}, {1, 0, 0}}, 3.0);
        REQUIRE(h.hit);
        CHECK(h.t == 2.0);
        CHECK(h.cell == std::array<uint32_t, 3>{0, 2, 1});
        CHECK_FALSE(traceIso(v, {{-2, 2.5, 1.5}, {1, 0, 0}}, 3.0, 1).hit); // a zero run is one crossing
    }
    SUBCASE("flat region after a rise and after a fall") {
        for (bool fromAbove : {false, true}) {
            INFO("from above ", fromAbove);
            Volume v = analytic::linearRamp({12, 5, 4}, {0, 0, 0});
            for (uint32_t k = 0; k < 4; ++k)
                for (uint32_t j = 0; j < 5; ++j)
                    for (uint32_t i = 0; i < 12; ++i)
                        setF32(v, i, j, k,
                               fromAbove ? float(std::max(8.0 - i, 4.0)) : float(std::min(i, 4u)));
            const auto h = traceIso(v, {{-1, 2.5, 1.5}, unit(1, 0.01, 0.02)}, 4.0);
            REQUIRE(h.hit);
            CHECK(std::abs(h.indexPos.x - 4.0) < kEps);
            CHECK_FALSE(traceIso(v, {{-1, 2.5, 1.5}, unit(1, 0.01, 0.02)}, 4.0, 1).hit);
        }
    }
}

TEST_CASE("oracle: volumes thinner than two samples have no cells") {
    const Volume v = analytic::linearRamp({24, 16, 1}, {1, 0, 0});
    CHECK_FALSE(traceIso(v, {{-5, 7.3, 0}, {1, 0, 0}}, 10.25).hit);
}

TEST_CASE("oracle: Marschner-Lobb signal crosses where the formula says") {
    const auto s = analytic::marschnerLobb(41);
    CHECK(s.iso == 0.5);
    CHECK(s.vol.valueMin >= 0.0);
    CHECK(s.vol.valueMax <= 1.0);
    // Along x = 0.5, y = 0 (sample planes) the signal depends on z alone: sin(pi z / 2) = 1 + alpha(1 + rho)
    // - 1.25.
    const double rho = std::cos(2 * std::numbers::pi * 6 * std::cos(std::numbers::pi * 0.5 / 2));
    const double z = 2 / std::numbers::pi * std::asin(1 + 0.25 * (1 + rho) - 1.25);
    const auto h = traceIso(s.vol, {{0.5, 0, 3}, {0, 0, -1}}, s.iso);
    REQUIRE(h.hit);
    CHECK(std::abs(h.worldPos.z - z) < 0.01);
}

TEST_CASE("oracle: metrics are zero for identical inputs") {
    oracle::Image ref{3, 2, std::vector<oracle::Hit>(6)};
    std::vector<float> depth(6, -1.0f);
    std::vector<uint64_t> ids(6, UINT64_MAX);
    std::vector<glm::vec3> normals(6, glm::vec3(0));
    for (int p : {0, 2, 3, 5}) {
        auto& h = ref.hits[size_t(p)];
        h.hit = true;
        h.t = 10.5 + p;
        h.cellId = uint64_t(100 + p);
        h.gradient = {0, 0, -2.0 * (p + 1)};
        depth[size_t(p)] = float(h.t);
        ids[size_t(p)] = h.cellId;
        normals[size_t(p)] = {0, 0, 1};
    }
    Volume v;
    const auto m = oracle::compare(ref, v, depth, ids, normals);
    INFO(oracle::format(m));
    CHECK(m.pixels == 6);
    CHECK(m.bothHit == 4);
    CHECK(m.hitMissMismatch == 0.0);
    CHECK(m.depthP50 == 0.0);
    CHECK(m.depthP99 == 0.0);
    CHECK(m.depthMax == 0.0);
    CHECK(m.idMismatch == 0.0);
    CHECK(m.normalP99Deg == 0.0);
    CHECK(m.nonFinite == 0);
    const auto n = oracle::compare(ref, v, depth, {});
    CHECK(std::isnan(n.idMismatch));
    CHECK(std::isnan(n.normalP99Deg));
}

TEST_CASE("oracle: metrics on a constructed difference") {
    // 4x2 image. Oracle: pixels 0..5 hit at t = 10, ids 0..5. GPU: 0..4 hit with depth errors of
    // 0, 0, 0.5, 1, 2 voxels (voxel = 0.5), pixel 5 misses, pixel 6 hits spuriously, id of 3 is wrong,
    // normal of 4 is 90 degrees off, normal of 1 is NaN.
    oracle::Image ref{4, 2, std::vector<oracle::Hit>(8)};
    for (int p = 0; p < 6; ++p) {
        auto& h = ref.hits[size_t(p)];
        h.hit = true;
        h.t = 10.0;
        h.cellId = uint64_t(p);
        h.gradient = {0, -1, 0};
    }
    Volume v;
    v.spacing = {0.5, 1.0, 2.0};
    std::vector<float> depth{10.0f, 10.0f, 10.25f, 10.5f, 9.0f, -1.0f, 3.0f, -1.0f};
    std::vector<uint64_t> ids{0, 1, 2, 77, 4, 0xFFFFFFFF, 6, UINT64_MAX};
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::vector<glm::vec3> normals(8, glm::vec3(0, 1, 0));
    normals[4] = {1, 0, 0};
    normals[1] = {nan, 0, 0};
    const auto m = oracle::compare(ref, v, depth, ids, normals);
    INFO(oracle::format(m));
    CHECK(m.pixels == 8);
    CHECK(m.bothHit == 5);
    CHECK(m.hitMissMismatch == 0.25);
    CHECK(m.depthP50 == 0.5); // nearest rank 3 of {0, 0, 0.5, 1, 2}
    CHECK(m.depthP99 == 2.0);
    CHECK(m.depthMax == 2.0);
    CHECK(m.worstX == 0);
    CHECK(m.worstY == 1);
    CHECK(m.idMismatch == 0.2);
    CHECK(m.normalP99Deg == doctest::Approx(90.0));
    CHECK(m.nonFinite == 1);

    depth[0] = nan;
    const auto k = oracle::compare(ref, v, depth, ids, normals);
    CHECK(k.nonFinite == 2);
    CHECK(k.hitMissMismatch == 0.25); // a NaN depth is a broken hit, not a miss
    CHECK(k.depthMax == 2.0);
    CHECK(oracle::format(k).find("non-finite 2") != std::string::npos);
}
