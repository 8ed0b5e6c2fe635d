// Explicit scene exploration (paper §5) on the GPU against the float64 oracle: surface peeling windows
// (each peel skips one more crossing), cropping through a shell (no caps), voxel ids per pixel (what
// picking reads), and seed preview colouring of the hit cells.
#include "gpu_fixture.hpp"

#include "oracle/analytic.hpp"
#include "oracle/metrics.hpp"
#include "oracle/oracle.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <vector>

using namespace iso;

namespace {

constexpr int kSize = 48;

analytic::ShellScene shells() {
    return analytic::nestedShells(40, {6.0, 11.0, 16.0});
}

std::vector<uint64_t> ids64(const Frame& f) {
    std::vector<uint64_t> ids(f.voxelIds.size());
    for (std::size_t i = 0; i < ids.size(); ++i)
        ids[i] = f.voxelIds[i] == 0xFFFFFFFFu ? UINT64_MAX : f.voxelIds[i];
    return ids;
}

uint64_t nonFinite(const Frame& f) {
    uint64_t n = 0;
    for (float v : f.rgba) n += std::isfinite(v) ? 0 : 1;
    for (float v : f.depth) n += std::isfinite(v) ? 0 : 1;
    return n;
}

RenderSettings settingsFor(const analytic::ShellScene& sc, const Camera& cam) {
    RenderSettings s;
    s.width = s.height = kSize;
    s.camera = cam;
    s.iso = sc.iso;
    return s;
}

// The oracle image whose pixel p is the (peel[p] + 1)-th crossing: one oracle render per skip count used.
oracle::Image oracleByPeel(const Volume& vol, const RenderSettings& s, const std::vector<uint32_t>& peel) {
    uint32_t most = 0;
    for (uint32_t c : peel) most = std::max(most, c);
    oracle::Image out;
    for (uint32_t skip = 0; skip <= most; ++skip) {
        oracle::Options opt;
        opt.iso = s.iso;
        opt.crop = s.crop;
        opt.skipCrossings = int(skip);
        oracle::Image ref = oracle::render(vol, s.camera, s.width, s.height, opt);
        if (skip == 0) out = ref;
        for (std::size_t p = 0; p < ref.hits.size(); ++p)
            if ((peel.empty() ? 0u : peel[p]) == skip) out.hits[p] = ref.hits[p];
    }
    return out;
}

// Exact per-pixel comparison of the render's ids with the oracle's cellId (misses on both sides agree).
uint64_t idDisagreements(const oracle::Image& ref, const Frame& f) {
    uint64_t bad = 0;
    for (std::size_t p = 0; p < ref.hits.size(); ++p) {
        const uint64_t want = ref.hits[p].hit ? ref.hits[p].cellId : UINT64_MAX;
        const uint64_t got = f.voxelIds[p] == 0xFFFFFFFFu ? UINT64_MAX : f.voxelIds[p];
        bad += want != got;
    }
    return bad;
}

// The foundation's targets: hit/miss and id mismatch <= 1e-3, depth p99 <= 1e-3 voxel.
oracle::Metrics checkAgainst(const oracle::Image& ref, const Volume& vol, const Frame& f,
                             const std::string& what) {
    oracle::Metrics m = oracle::compare(ref, vol, f.depth, ids64(f));
    m.nonFinite += nonFinite(f);
    MESSAGE(what << ": " << oracle::format(m) << ", exact id disagreements " << idDisagreements(ref, f));
    CHECK(m.bothHit > 100);
    CHECK(m.hitMissMismatch <= 1e-3);
    CHECK(m.depthP99 <= 1e-3);
    CHECK(m.idMismatch <= 1e-3);
    CHECK(m.nonFinite == 0);
    return m;
}

std::vector<Camera> views(const Volume& vol) {
    Camera ortho = test::orbitCamera(vol, -60.0, 35.0);
    ortho.orthographic = true;
    ortho.height = 40.0;
    return {test::orbitCamera(vol, 30.0, 20.0), ortho};
}

} // namespace

TEST_CASE("explore: peel windows show the 2nd and 3rd crossings of nested shells") {
    auto sc = shells();
    Renderer renderer(test::gpu());
    renderer.setVolume(sc.vol);
    for (const Camera& cam : views(sc.vol)) {
        CAPTURE(cam.orthographic);
        RenderSettings s = settingsFor(sc, cam);
        Frame plain = renderer.render(s, {true, true, true});
        checkAgainst(oracleByPeel(sc.vol, s, {}), sc.vol, plain, "no peel");

        // One window: its pixels skip the first crossing (entering the outer shell), so they show the
        // 2nd (leaving it, at the middle radius).
        addPeelWindow(s.peelBuffer, kSize, kSize, 8, 6, 32, 30);
        Frame one = renderer.render(s, {true, true, true});
        oracle::Image refOne = oracleByPeel(sc.vol, s, s.peelBuffer);
        checkAgainst(refOne, sc.vol, one, "one window");
        // Two overlapping windows: the overlap skips two crossings and shows the 3rd (the inner shell).
        addPeelWindow(s.peelBuffer, kSize, kSize, 18, 16, 44, 42);
        Frame two = renderer.render(s, {true, true, true});
        oracle::Image refTwo = oracleByPeel(sc.vol, s, s.peelBuffer);
        checkAgainst(refTwo, sc.vol, two, "two windows");

        // The windows really changed the picture: where both renders hit, pixels with a higher peel count
        // lie deeper, and a peeled ray that had a hit only misses if its later crossings do not exist.
        int deeper = 0, peeled = 0, inOverlap = 0;
        for (std::size_t p = 0; p < s.peelBuffer.size(); ++p) {
            if (s.peelBuffer[p] == 0 || plain.depth[p] < 0.0f) continue;
            ++peeled;
            inOverlap += s.peelBuffer[p] == 2 && two.depth[p] >= 0.0f;
            if (two.depth[p] >= 0.0f) deeper += two.depth[p] > plain.depth[p] + 1.0f;
            if (s.peelBuffer[p] == 2 && one.depth[p] >= 0.0f && two.depth[p] >= 0.0f)
                CHECK(two.depth[p] > one.depth[p]);
        }
        MESSAGE("peeled pixels with a hit " << peeled << ", deeper by > 1 " << deeper << ", overlap hits "
                                            << inOverlap);
        CHECK(inOverlap > 50);
        CHECK(deeper > peeled / 2);
        // Outside the windows nothing changes.
        for (std::size_t p = 0; p < s.peelBuffer.size(); ++p)
            if (s.peelBuffer[p] == 0) {
                CHECK(two.depth[p] == plain.depth[p]);
                CHECK(two.voxelIds[p] == plain.voxelIds[p]);
            }
    }
    CHECK(test::gpu().validationMessages() == 0);
}

TEST_CASE("explore: a crop box through the outer shell shows what lies behind it, without caps") {
    auto sc = shells();
    Renderer renderer(test::gpu());
    renderer.setVolume(sc.vol);
    // The centre is 19.5; the outer shell spans 3.5 .. 35.5. z <= 31 cuts the outer shell's cap off
    // (11.5 from the centre: between the middle and outer radii), x >= 4.5 grazes its other side.
    const std::array<double, 6> crops[] = {{0.0, 0.0, 0.0, 39.0, 39.0, 31.0},
                                           {4.5, 0.0, 0.0, 39.0, 39.0, 30.25}};
    Camera top = test::orbitCamera(sc.vol, 10.0, 80.0);
    for (const auto& crop : crops) {
        for (const Camera& cam : {top, views(sc.vol)[0]}) {
            RenderSettings s = settingsFor(sc, cam);
            s.crop = crop;
            Frame f = renderer.render(s, {true, true, true});
            const oracle::Image ref = oracleByPeel(sc.vol, s, {});
            checkAgainst(ref, sc.vol, f, "crop");
            // Some rays enter the crop box through the cut inside the outer shell's material and show the
            // middle shell: the hit lies at the middle radius.
            int middle = 0;
            for (const auto& h : ref.hits)
                if (h.hit && std::abs(glm::length(h.indexPos - sc.centre) - 11.0) < 0.5) ++middle;
            MESSAGE("pixels showing the middle shell through the cut: " << middle);
            CHECK(middle > 20);
        }
    }
    // Peeling inside a crop: the oracle with the same crop and skip counts.
    RenderSettings s = settingsFor(sc, top);
    s.crop = crops[0];
    addPeelWindow(s.peelBuffer, kSize, kSize, 0, 0, kSize, kSize / 2);
    Frame f = renderer.render(s, {true, true, true});
    checkAgainst(oracleByPeel(sc.vol, s, s.peelBuffer), sc.vol, f, "crop and peel");
    CHECK(test::gpu().validationMessages() == 0);
}

TEST_CASE("explore: voxel ids equal the oracle's cell ids per pixel") {
    auto sc = shells();
    Renderer renderer(test::gpu());
    renderer.setVolume(sc.vol);
    for (const Camera& cam : views(sc.vol)) {
        CAPTURE(cam.orthographic);
        RenderSettings s = settingsFor(sc, cam);
        // Ids only: the graph keeps the passes these need.
        Frame f = renderer.render(s, {false, false, true});
        REQUIRE(f.voxelIds.size() == std::size_t(kSize * kSize));
        oracle::Image ref = oracleByPeel(sc.vol, s, {});
        uint64_t compared = 0, bad = 0;
        for (std::size_t p = 0; p < ref.hits.size(); ++p) {
            if (!ref.hits[p].hit) continue;
            ++compared;
            // A hit's id names a cell of the volume, and it is the cell the oracle's hit lies in.
            CHECK(f.voxelIds[p] < sc.vol.sampleCount());
            bad += f.voxelIds[p] != ref.hits[p].cellId;
        }
        const uint64_t all = idDisagreements(ref, f);
        MESSAGE("ids: hit pixels " << compared << ", disagreements on hits " << bad << ", on all pixels "
                                   << all);
        CHECK(compared > 500);
        CHECK(double(bad) <= 1e-3 * double(compared));
        CHECK(double(all) <= 1e-3 * double(f.voxelIds.size()));
    }
    CHECK(test::gpu().validationMessages() == 0);
}

TEST_CASE("explore: seed preview colours exactly the pixels whose cell is a seed") {
    auto sc = shells();
    Renderer renderer(test::gpu());
    renderer.setVolume(sc.vol);
    RenderSettings s = settingsFor(sc, test::orbitCamera(sc.vol, 30.0, 20.0));
    s.shade = false;
    Frame first = renderer.render(s, {true, true, true});

    // Ids by how many pixels show them, most first; seeds from the most frequent ones so that each colour
    // covers several pixels.
    std::map<uint32_t, int> counts;
    for (uint32_t id : first.voxelIds)
        if (id != 0xFFFFFFFFu) ++counts[id];
    std::vector<std::pair<int, uint32_t>> byCount;
    for (auto [id, n] : counts) byCount.push_back({n, id});
    std::sort(byCount.rbegin(), byCount.rend());
    REQUIRE(byCount.size() > 12);
    // Unsorted, with a duplicate, and with ids no pixel shows (0 and one past the last cell).
    std::vector<uint32_t> fg{byCount[4].second, byCount[0].second, byCount[7].second, byCount[0].second, 0u};
    std::vector<uint32_t> bg{byCount[1].second, byCount[10].second, byCount[5].second,
                             uint32_t(sc.vol.sampleCount())};
    s.foregroundSeeds = fg;
    s.backgroundSeeds = bg;
    Frame seeded = renderer.render(s, {true, true, true});
    CHECK(nonFinite(first) == 0);
    CHECK(nonFinite(seeded) == 0);

    const std::set<uint32_t> fgSet(fg.begin(), fg.end()), bgSet(bg.begin(), bg.end());
    const glm::vec3 bgColour = s.shading.background;
    int nFg = 0, nBg = 0, nMaterial = 0, nMiss = 0, bad = 0, idChanged = 0;
    for (std::size_t p = 0; p < seeded.voxelIds.size(); ++p) {
        const uint32_t id = seeded.voxelIds[p];
        idChanged += id != first.voxelIds[p];
        glm::vec3 want;
        if (id == 0xFFFFFFFFu) {
            want = bgColour, ++nMiss;
        } else if (fgSet.count(id)) {
            want = s.foregroundColour, ++nFg;
        } else if (bgSet.count(id)) {
            want = s.backgroundColour, ++nBg;
        } else {
            want = s.shading.material, ++nMaterial;
        }
        const glm::vec3 got(seeded.rgba[4 * p], seeded.rgba[4 * p + 1], seeded.rgba[4 * p + 2]);
        const glm::vec3 d = glm::abs(got - want);
        bad += std::max(d.x, std::max(d.y, d.z)) > 1e-6f;
        // Without seeds every hit shows the material colour.
        if (first.voxelIds[p] != 0xFFFFFFFFu) {
            const glm::vec3 g0(first.rgba[4 * p], first.rgba[4 * p + 1], first.rgba[4 * p + 2]);
            const glm::vec3 d0 = glm::abs(g0 - s.shading.material);
            bad += std::max(d0.x, std::max(d0.y, d0.z)) > 1e-6f;
        }
    }
    MESSAGE("seeds: foreground pixels " << nFg << ", background " << nBg << ", material " << nMaterial
                                        << ", misses " << nMiss << ", wrong colours " << bad
                                        << ", ids changed by seeding " << idChanged);
    CHECK(nFg >= byCount[0].first + byCount[4].first + byCount[7].first);
    CHECK(nBg >= byCount[1].first + byCount[5].first + byCount[10].first);
    CHECK(nMaterial > 100);
    CHECK(bad == 0);
    CHECK(idChanged == 0);

    // Seeds also colour peeled hits: the ids the peeled render shows decide the colours there.
    addPeelWindow(s.peelBuffer, kSize, kSize, 0, 0, kSize, kSize);
    Frame peeled = renderer.render(s, {true, true, true});
    int badPeeled = 0;
    for (std::size_t p = 0; p < peeled.voxelIds.size(); ++p) {
        const uint32_t id = peeled.voxelIds[p];
        const glm::vec3 want = id == 0xFFFFFFFFu ? bgColour
                               : fgSet.count(id) ? s.foregroundColour
                               : bgSet.count(id) ? s.backgroundColour
                                                 : s.shading.material;
        const glm::vec3 got(peeled.rgba[4 * p], peeled.rgba[4 * p + 1], peeled.rgba[4 * p + 2]);
        const glm::vec3 d = glm::abs(got - want);
        badPeeled += std::max(d.x, std::max(d.y, d.z)) > 1e-6f;
    }
    CHECK(badPeeled == 0);
    CHECK(nonFinite(peeled) == 0);

    // Background seeds alone (an empty foreground list).
    s.peelBuffer.clear();
    s.foregroundSeeds.clear();
    Frame bgOnly = renderer.render(s, {true, true, true});
    int badBgOnly = 0, nBgOnly = 0;
    for (std::size_t p = 0; p < bgOnly.voxelIds.size(); ++p) {
        const uint32_t id = bgOnly.voxelIds[p];
        if (id == 0xFFFFFFFFu) continue;
        const glm::vec3 want = bgSet.count(id) ? s.backgroundColour : s.shading.material;
        nBgOnly += bgSet.count(id) ? 1 : 0;
        const glm::vec3 d =
            glm::abs(glm::vec3(bgOnly.rgba[4 * p], bgOnly.rgba[4 * p + 1], bgOnly.rgba[4 * p + 2]) - want);
        badBgOnly += std::max(d.x, std::max(d.y, d.z)) > 1e-6f;
    }
    CHECK(nBgOnly == nBg);
    CHECK(badBgOnly == 0);
    CHECK(test::gpu().validationMessages() == 0);
}
