// The shared ray core compiled as C++: cubic coefficients, root isolation and the 3D-DDA, each
// checked against an independent double-precision computation.
#include <doctest/doctest.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

namespace iso::rc {
// The core's fetch hook: tests point it at whatever samples they construct.
inline std::function<float(glm::ivec3)> gTestFetch;
inline float rcFetch(glm::ivec3 p) {
    return gTestFetch(p);
}
} // namespace iso::rc

#include "ray_core.h"

using namespace iso::rc;

namespace {

double trilinear(const float c[8], glm::dvec3 u) {
    double v = 0.0;
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i)
                v += c[i + 2 * j + 4 * k] * (i ? u.x : 1 - u.x) * (j ? u.y : 1 - u.y) * (k ? u.z : 1 - u.z);
    return v;
}

float cubicOf(double r0, double r1, double r2, double s) {
    return float((s - r0) * (s - r1) * (s - r2));
}

// Coefficients of (s - r0)(s - r1)(s - r2) times `scale`.
vec4 fromRoots(double r0, double r1, double r2, double scale = 1.0) {
    return vec4(float(-r0 * r1 * r2 * scale), float((r0 * r1 + r0 * r2 + r1 * r2) * scale),
                float(-(r0 + r1 + r2) * scale), float(scale));
}

struct Visit {
    glm::ivec3 cell;
    double t0, t1;
};

// Brute force: every cell of the grid whose box the ray crosses with positive length, in order.
std::vector<Visit> crossedCells(glm::dvec3 o, glm::dvec3 d, glm::ivec3 dims) {
    std::vector<Visit> out;
    for (int k = 0; k < dims.z - 1; ++k)
        for (int j = 0; j < dims.y - 1; ++j)
            for (int i = 0; i < dims.x - 1; ++i) {
                double t0 = 0.0, t1 = 1e30;
                bool ok = true;
                for (int a = 0; a < 3 && ok; ++a) {
                    double lo = (a == 0 ? i : a == 1 ? j : k), hi = lo + 1;
                    if (d[a] == 0.0) {
                        ok = o[a] >= lo && o[a] <= hi;
                    } else {
                        double ta = (lo - o[a]) / d[a], tb = (hi - o[a]) / d[a];
                        t0 = std::max(t0, std::min(ta, tb));
                        t1 = std::min(t1, std::max(ta, tb));
                    }
                }
                if (ok && t1 - t0 > 1e-9) out.push_back({{i, j, k}, t0, t1});
            }
    std::sort(out.begin(), out.end(), [](const Visit& a, const Visit& b) { return a.t0 < b.t0; });
    return out;
}

std::vector<Visit> ddaCells(vec3 o, vec3 d, ivec3 dims) {
    std::vector<Visit> out;
    RcDda s;
    vec3 bmax = vec3(dims - ivec3(1));
    if (!rcDdaBegin(o, d, vec3(0.0f), bmax, dims, s)) return out;
    for (int n = 0; n < 1000; ++n) {
        vec3 tExit = rcDdaAxisExits(o, s);
        float tOut = rcDdaCellExit(tExit, s);
        out.push_back({s.cell, s.tIn, tOut});
        if (!rcDdaStep(s, tExit, tOut)) break;
    }
    return out;
}

void checkSameCells(vec3 o, vec3 d, ivec3 dims) {
    auto want = crossedCells(glm::dvec3(o), glm::dvec3(d), dims);
    auto got = ddaCells(o, d, dims);
    INFO("ray o=(" << o.x << "," << o.y << "," << o.z << ") d=(" << d.x << "," << d.y << "," << d.z << ")");
    REQUIRE(got.size() == want.size());
    for (size_t i = 0; i < got.size(); ++i) {
        INFO("visit " << i);
        CHECK(got[i].cell == want[i].cell);
        CHECK(std::abs(got[i].t0 - want[i].t0) < 1e-4);
        CHECK(std::abs(got[i].t1 - want[i].t1) < 1e-4);
    }
}

} // namespace

TEST_CASE("raycore: cubic from 8 corners equals the trilinear interpolant along the ray") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> val(-100.0f, 100.0f), pos(0.0f, 1.0f), dir(-1.5f, 1.5f);
    for (int trial = 0; trial < 200; ++trial) {
        float c[8];
        for (float& x : c) x = val(rng);
        vec3 a(pos(rng), pos(rng), pos(rng)), d(dir(rng), dir(rng), dir(rng));
        float iso = val(rng);
        vec4 k = rcCellCubic(c, a, d, iso);
        for (int i = 0; i <= 10; ++i) {
            double s = 0.1 * i;
            double ref = trilinear(c, glm::dvec3(a) + s * glm::dvec3(d)) - iso;
            CHECK(std::abs(rcCubicAt(k, float(s)) - ref) < 1e-3);
        }
    }
}

TEST_CASE("raycore: first root of cubics with one, two, three, a double and no root") {
    float s = -1.0f;
    SUBCASE("one root") {
        REQUIRE(rcFirstRoot(fromRoots(0.3, 5.0, 7.0), 1.0f, s));
        CHECK(s == doctest::Approx(0.3).epsilon(1e-6));
    }
    SUBCASE("two roots in the cell: the first is taken") {
        REQUIRE(rcFirstRoot(fromRoots(0.2, 0.7, 3.0), 1.0f, s));
        CHECK(s == doctest::Approx(0.2).epsilon(1e-6));
    }
    SUBCASE("three roots in the cell: the first is taken") {
        REQUIRE(rcFirstRoot(fromRoots(0.15, 0.5, 0.85, -4.0), 1.0f, s));
        CHECK(s == doctest::Approx(0.15).epsilon(1e-6));
    }
    SUBCASE("three close roots") {
        REQUIRE(rcFirstRoot(fromRoots(0.40, 0.45, 0.5), 1.0f, s));
        CHECK(s == doctest::Approx(0.40).epsilon(1e-5));
    }
    SUBCASE("a double root (tangent) is a hit") {
        // (s - 0.5)^2: the derivative's root is exactly 0.5 and g(0.5) is exactly 0 in float.
        REQUIRE(rcFirstRoot(vec4(0.25f, -1.0f, 1.0f, 0.0f), 1.0f, s));
        CHECK(s == 0.5f);
    }
    SUBCASE("no root") {
        CHECK_FALSE(rcFirstRoot(fromRoots(1.5, 2.0, -0.5, -1.0), 1.0f, s));
        CHECK_FALSE(rcFirstRoot(vec4(1.0f, 0.0f, 0.0f, 0.0f), 1.0f, s));
    }
    SUBCASE("an exact zero at the entry is a hit (f >= iso is inside)") {
        REQUIRE(rcFirstRoot(vec4(0.0f, 1.0f, 0.0f, 0.0f), 1.0f, s));
        CHECK(s == 0.0f);
    }
    SUBCASE("an exact zero at the exit is a hit") {
        REQUIRE(rcFirstRoot(vec4(-1.0f, 1.0f, 0.0f, 0.0f), 1.0f, s));
        CHECK(s == 1.0f);
    }
    SUBCASE("root beyond the cell is not taken") {
        CHECK_FALSE(rcFirstRoot(fromRoots(1.2, 3.0, 4.0), 1.0f, s));
    }
    (void)cubicOf;
}

TEST_CASE("raycore: DDA visits exactly the cells a ray crosses") {
    ivec3 dims(6, 5, 7);
    SUBCASE("axis-aligned rays") {
        checkSameCells(vec3(-2.0f, 1.5f, 2.5f), vec3(1, 0, 0), dims);
        checkSameCells(vec3(2.5f, 9.0f, 0.5f), vec3(0, -1, 0), dims);
        checkSameCells(vec3(1.25f, 3.75f, -1.0f), vec3(0, 0, 1), dims);
    }
    SUBCASE("ray along a grid line and on a face") {
        // Such a ray lies on the shared boundary of 2 (face) or 4 (grid line) cells, where the
        // interpolant is the same from either side: one cell per step, covering the whole ray.
        for (vec3 o : {vec3(-1.0f, 2.0f, 3.5f), vec3(-1.0f, 2.0f, 3.0f)}) {
            auto got = ddaCells(o, vec3(1, 0, 0), dims);
            REQUIRE(got.size() == size_t(dims.x - 1));
            for (size_t i = 0; i < got.size(); ++i) {
                CHECK(got[i].cell.x == int(i));
                CHECK(float(got[i].cell.y) <= o.y);
                CHECK(o.y <= float(got[i].cell.y + 1));
                CHECK(float(got[i].cell.z) <= o.z);
                CHECK(o.z <= float(got[i].cell.z + 1));
                CHECK(got[i].t0 == doctest::Approx(1.0 + double(i)));
            }
        }
    }
    SUBCASE("diagonal rays through edges and corners") {
        checkSameCells(vec3(-1.0f, -1.0f, 2.5f), glm::normalize(vec3(1, 1, 0)), dims);
        checkSameCells(vec3(-1.0f, -1.0f, -1.0f), glm::normalize(vec3(1, 1, 1)), dims);
        checkSameCells(vec3(7.0f, 0.5f, 8.0f), glm::normalize(vec3(-1, 0, -1)), dims);
    }
    SUBCASE("ray starting inside a cell") {
        checkSameCells(vec3(2.3f, 1.7f, 3.1f), glm::normalize(vec3(0.3f, -0.8f, 0.5f)), dims);
    }
    SUBCASE("random oblique rays") {
        std::mt19937 rng(11);
        std::uniform_real_distribution<float> p(-3.0f, 10.0f), q(-1.0f, 1.0f);
        for (int i = 0; i < 200; ++i) {
            vec3 d(q(rng), q(rng), q(rng));
            if (glm::length(d) < 0.1f) continue;
            vec3 o(p(rng), p(rng), p(rng));
            auto want = crossedCells(glm::dvec3(o), glm::dvec3(glm::normalize(d)), dims);
            auto got = ddaCells(o, glm::normalize(d), dims);
            // Float rounding may add a visit of (almost) zero length near an edge; every crossed
            // cell with a real length is visited, in order.
            std::vector<Visit> gotReal, wantReal;
            for (auto& v : got)
                if (v.t1 - v.t0 > 1e-4) gotReal.push_back(v);
            for (auto& v : want)
                if (v.t1 - v.t0 > 1e-4) wantReal.push_back(v);
            REQUIRE(gotReal.size() == wantReal.size());
            for (size_t k = 0; k < gotReal.size(); ++k) CHECK(gotReal[k].cell == wantReal[k].cell);
        }
    }
    SUBCASE("a ray that misses the box visits nothing") {
        CHECK(ddaCells(vec3(-1.0f, 10.0f, 1.0f), vec3(1, 0, 0), dims).empty());
    }
}

TEST_CASE("raycore: first hit on a linear ramp is exact") {
    // f = 2*i + j, iso 7.5: for a ray along +i at j = 1.5 the hit is at i = 3.
    gTestFetch = [](glm::ivec3 p) { return float(2 * p.x + p.y); };
    ivec3 dims(8, 4, 4);
    RcHit h = rcFirstHit(vec3(-2.0f, 1.5f, 1.25f), vec3(1, 0, 0), vec3(0.0f), vec3(dims - 1), dims, 7.5f);
    REQUIRE(h.t >= 0.0f);
    CHECK(h.t == doctest::Approx(5.0).epsilon(1e-6));
    CHECK(h.cell == ivec3(2, 1, 1)); // the root at i = 3 lies on a face: the cell reached first holds it
    h = rcFirstHit(vec3(20.0f, 1.5f, 1.25f), vec3(-1, 0, 0), vec3(0.0f), vec3(dims - 1), dims, 7.5f);
    REQUIRE(h.t >= 0.0f);
    // Enters at i = 7 where f = 15.5 >= iso (inside), so the first zero is on the way out, at i = 3.
    CHECK(h.t == doctest::Approx(20.0 - 3.0).epsilon(1e-6));
    CHECK(h.cell == ivec3(3, 1, 1));
}

TEST_CASE("raycore: a NaN corner hides only its own cells") {
    gTestFetch = [](glm::ivec3 p) { return p == glm::ivec3(3, 1, 1) ? NAN : float(p.x); };
    ivec3 dims(8, 4, 4);
    // Along +i at j = k = 1.5, cells (2..3, 1, 1) touch the NaN sample; iso 2.5 lies in cell 2.
    RcHit h = rcFirstHit(vec3(-1.0f, 1.5f, 1.5f), vec3(1, 0, 0), vec3(0.0f), vec3(dims - 1), dims, 2.5f);
    CHECK(h.t < 0.0f);
    // A ray that misses those cells still finds the surface.
    h = rcFirstHit(vec3(-1.0f, 2.5f, 2.5f), vec3(1, 0, 0), vec3(0.0f), vec3(dims - 1), dims, 2.5f);
    REQUIRE(h.t >= 0.0f);
    CHECK(h.t == doctest::Approx(3.5));
}

TEST_CASE("raycore: successive roots in one cell are each found once") {
    vec4 c = fromRoots(0.15, 0.5, 0.85, -4.0);
    float s = -1.0f, prev = -1.0f;
    std::vector<float> roots;
    while (rcNextRoot(c, 1.0f, prev, s)) {
        roots.push_back(s);
        prev = s;
        REQUIRE(roots.size() < 5);
    }
    REQUIRE(roots.size() == 3);
    CHECK(roots[0] == doctest::Approx(0.15).epsilon(1e-5));
    CHECK(roots[1] == doctest::Approx(0.5).epsilon(1e-5));
    CHECK(roots[2] == doctest::Approx(0.85).epsilon(1e-5));
    // A tangent touch is one crossing, not two.
    roots.clear();
    prev = -1.0f;
    while (rcNextRoot(vec4(0.25f, -1.0f, 1.0f, 0.0f), 1.0f, prev, s)) {
        roots.push_back(s);
        prev = s;
        REQUIRE(roots.size() < 5);
    }
    CHECK(roots.size() == 1);
}

TEST_CASE("raycore: skipping crossings counts every crossing once, also on cell faces") {
    ivec3 dims(10, 3, 3);
    SUBCASE("crossings inside cells") {
        gTestFetch = [](glm::ivec3 p) { return float(p.x % 2); }; // crosses 0.5 in every cell
        for (int skip = 0; skip < 9; ++skip) {
            RcHit h = rcTraceIso(vec3(-1.0f, 1.0f, 1.0f), vec3(1, 0, 0), vec3(0.0f), vec3(dims - 1), dims,
                                 0.5f, skip);
            REQUIRE(h.t >= 0.0f);
            CHECK(h.t == doctest::Approx(1.5 + skip).epsilon(1e-6));
            CHECK(h.cell.x == skip);
        }
        CHECK(
            rcTraceIso(vec3(-1.0f, 1.0f, 1.0f), vec3(1, 0, 0), vec3(0.0f), vec3(dims - 1), dims, 0.5f, 9).t <
            0.0f);
    }
    SUBCASE("crossings exactly on shared faces") {
        // Samples 0,1,2,1,0,1,2,... with iso 1: every crossing sits on a sample, i.e. on a face.
        gTestFetch = [](glm::ivec3 p) { return float(std::abs((p.x + 2) % 4 - 2)); };
        std::vector<float> ts;
        for (int skip = 0; skip < 12; ++skip) {
            RcHit h = rcTraceIso(vec3(-1.0f, 1.0f, 1.0f), vec3(1, 0, 0), vec3(0.0f), vec3(dims - 1), dims,
                                 1.0f, skip);
            if (h.t < 0.0f) break;
            ts.push_back(h.t - 1.0f); // as a sample index
        }
        // f - 1 is zero at i = 1, 3, 5, 7, 9 (and has the sign pattern -,0,+,0,-,...).
        REQUIRE(ts.size() == 5);
        for (size_t k = 0; k < ts.size(); ++k) CHECK(ts[k] == doctest::Approx(1.0 + 2.0 * double(k)));
    }
}
