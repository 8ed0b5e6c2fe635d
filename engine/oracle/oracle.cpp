#include "oracle/oracle.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <thread>

namespace iso::oracle {

namespace {

// Uniform sub-intervals per cell. The cubic along the ray is also split at its extrema, which alone
// makes every piece monotone (one root at most); the uniform samples are a second line of defence
// against an inaccurate extremum.
constexpr int kSubIntervals = 64;
// |f - iso| at or below this fraction of the cell's largest |corner - iso| counts as exactly zero, so
// that a root on a shared face evaluates to zero from either cell despite rounding.
constexpr double kZeroTol = 1e-12;

double mix(double a, double b, double t) {
    return (1.0 - t) * a + t * b;
} // exact at t = 0 and t = 1

// Corner c of a cell is at offset (c & 1, c >> 1 & 1, c >> 2 & 1).
double trilinear(const std::array<double, 8>& c, const glm::dvec3& l) {
    const double x00 = mix(c[0], c[1], l.x), x10 = mix(c[2], c[3], l.x);
    const double x01 = mix(c[4], c[5], l.x), x11 = mix(c[6], c[7], l.x);
    return mix(mix(x00, x10, l.y), mix(x01, x11, l.y), l.z);
}

glm::dvec3 trilinearGradient(const std::array<double, 8>& c, const glm::dvec3& l) {
    const double gx = mix(mix(c[1] - c[0], c[3] - c[2], l.y), mix(c[5] - c[4], c[7] - c[6], l.y), l.z);
    const double gy = mix(mix(c[2] - c[0], c[3] - c[1], l.x), mix(c[6] - c[4], c[7] - c[5], l.x), l.z);
    const double gz = mix(mix(c[4] - c[0], c[5] - c[1], l.x), mix(c[6] - c[2], c[7] - c[3], l.x), l.y);
    return {gx, gy, gz};
}

using Poly = std::array<double, 4>; // cubic, lowest power first

Poly mul(const Poly& a, const Poly& b) {
    Poly r{};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; i + j < 4; ++j) r[std::size_t(i + j)] += a[std::size_t(i)] * b[std::size_t(j)];
    return r;
}

// f along l(s) = l0 + d*s as a cubic in s, from the monomial form of the trilinear interpolant.
Poly alongRay(const std::array<double, 8>& c, const glm::dvec3& l0, const glm::dvec3& d) {
    const Poly u{l0.x, d.x, 0, 0}, v{l0.y, d.y, 0, 0}, w{l0.z, d.z, 0, 0};
    const double k[8] = {c[0],
                         c[1] - c[0],
                         c[2] - c[0],
                         c[4] - c[0],
                         c[3] - c[1] - c[2] + c[0],
                         c[5] - c[1] - c[4] + c[0],
                         c[6] - c[2] - c[4] + c[0],
                         c[7] - c[3] - c[5] - c[6] + c[1] + c[2] + c[4] - c[0]};
    const Poly uv = mul(u, v), uw = mul(u, w), vw = mul(v, w), uvw = mul(uv, w);
    Poly p{};
    const Poly* terms[7] = {&u, &v, &w, &uv, &uw, &vw, &uvw};
    p[0] = k[0];
    for (int t = 0; t < 7; ++t)
        for (int i = 0; i < 4; ++i) p[std::size_t(i)] += k[t + 1] * (*terms[t])[std::size_t(i)];
    return p;
}

// Roots of the derivative p1 + 2 p2 s + 3 p3 s^2 that lie strictly inside (0, len).
void extremaInside(const Poly& p, double len, std::vector<double>& out) {
    const double a = 3.0 * p[3], b = 2.0 * p[2], c = p[1];
    auto keep = [&](double s) {
        if (s > 0.0 && s < len) out.push_back(s);
    };
    if (a == 0.0) {
        if (b != 0.0) keep(-c / b);
        return;
    }
    const double disc = b * b - 4.0 * a * c;
    if (disc < 0.0) return;
    // The cancellation-free pair of quadratic roots.
    const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
    if (q != 0.0) keep(c / q);
    keep(q / a);
}

struct CellData {
    std::array<uint32_t, 3> idx;
    std::array<double, 8> raw; // stored values
    std::array<double, 8> g;   // raw - iso
    double tol;                // zero band for g
};

// The walk's state: the last sample seen (sign and t) and how many crossings were passed.
struct Walk {
    const Volume& vol;
    glm::dvec3 o, d; // index-space ray
    double iso;
    int want; // crossings to reach
    int found = 0;
    bool havePrev = false;
    int prevSign = 0;
    double prevT = 0.0;
    std::vector<double> ts; // scratch

    int sign(const CellData& c, double v) const { return v > c.tol ? 1 : (v < -c.tol ? -1 : 0); }

    double eval(const CellData& c, double t) const {
        return trilinear(c.g, o + t * d - glm::dvec3(c.idx[0], c.idx[1], c.idx[2]));
    }

    // Bisects a strict sign change on [lo, hi] (sign at lo is `slo`) down to adjacent doubles.
    double bisect(const CellData& c, double lo, double hi, int slo) const {
        for (int it = 0; it < 200; ++it) {
            const double mid = 0.5 * (lo + hi);
            if (mid <= lo || mid >= hi) break;
            const int sm = sign(c, eval(c, mid));
            if (sm == 0) return mid;
            (sm == slo ? lo : hi) = mid;
        }
        return 0.5 * (lo + hi);
    }

    bool loadCell(const std::array<uint32_t, 3>& idx, CellData& c) const {
        c.idx = idx;
        double scale = 0.0;
        for (uint32_t n = 0; n < 8; ++n) {
            c.raw[n] = vol.value(idx[0] + (n & 1), idx[1] + (n >> 1 & 1), idx[2] + (n >> 2 & 1));
            if (!std::isfinite(c.raw[n])) return false;
            c.g[n] = c.raw[n] - iso;
            scale = std::max(scale, std::abs(c.g[n]));
        }
        c.tol = kZeroTol * scale;
        return true;
    }

    // Visits the part [t0, t1] of the ray inside cell idx; returns the crossing t once the wanted one
    // is reached.
    std::optional<double> visit(const std::array<uint32_t, 3>& idx, double t0, double t1, CellData& c) {
        if (!loadCell(idx, c)) {
            havePrev = false; // no surface in here, and no sign change across it either
            return std::nullopt;
        }
        // A cell whose corners all have one strict sign keeps it throughout (trilinear weights are a
        // partition of unity), so nothing happens inside unless the previous sample disagrees.
        const auto [mn, mx] = std::minmax_element(c.g.begin(), c.g.end());
        const int uniform = *mn > c.tol ? 1 : (*mx < -c.tol ? -1 : 0);
        if (uniform != 0 && (!havePrev || prevSign != -uniform)) {
            havePrev = true, prevSign = uniform, prevT = t1;
            return std::nullopt;
        }

        ts.clear();
        const double len = t1 - t0;
        for (int m = 0; m <= kSubIntervals; ++m)
            ts.push_back(m == kSubIntervals ? t1 : t0 + len * m / kSubIntervals);
        if (len > 0.0) {
            const glm::dvec3 l0 = o + t0 * d - glm::dvec3(idx[0], idx[1], idx[2]);
            const size_t before = ts.size();
            extremaInside(alongRay(c.g, l0, d), len, ts);
            for (size_t m = before; m < ts.size(); ++m) ts[m] += t0;
            std::sort(ts.begin(), ts.end());
            ts.erase(std::unique(ts.begin(), ts.end()), ts.end());
        } else {
            ts.resize(1);
        }

        for (double t : ts) {
            if (havePrev && t == prevT) continue; // the shared face point keeps the previous cell's sign
            const int s = sign(c, eval(c, t));
            std::optional<double> crossing;
            if (s == 0 && !(havePrev && prevSign == 0))
                crossing = t; // a zero run counts at its start
            else if (s != 0 && havePrev && prevSign == -s)
                crossing = bisect(c, prevT, t, prevSign);
            havePrev = true, prevSign = s, prevT = t;
            if (crossing && ++found == want) return crossing;
        }
        return std::nullopt;
    }
};

uint32_t cellAlong(double pos, uint32_t n) {
    return uint32_t(std::clamp(std::floor(pos), 0.0, double(n) - 2.0));
}

} // namespace

Hit trace(const Volume& vol, const Ray& ray, const Options& opt) {
    const auto& n = vol.dims;
    if (n[0] < 2 || n[1] < 2 || n[2] < 2) return {}; // no cells

    // Index space: world = origin + M * ijk. The direction is not renormalised, so the ray parameter
    // stays the world distance.
    const glm::dmat3 m =
        vol.directions * glm::dmat3(glm::dvec3(vol.spacing.x, 0, 0), glm::dvec3(0, vol.spacing.y, 0),
                                    glm::dvec3(0, 0, vol.spacing.z));
    const glm::dmat3 mInv = glm::inverse(m);
    const glm::dvec3 o = mInv * (ray.origin - vol.origin), d = mInv * ray.dir;

    glm::dvec3 lo(0.0), hi(n[0] - 1.0, n[1] - 1.0, n[2] - 1.0);
    if (opt.crop) {
        const auto& c = *opt.crop;
        lo = glm::max(lo, glm::dvec3(c[0], c[1], c[2]));
        hi = glm::min(hi, glm::dvec3(c[3], c[4], c[5]));
    }

    // Slab clipping; a zero direction component constrains nothing but the origin (on the plane is in).
    double tmin = 0.0, tmax = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        if (!(lo[a] <= hi[a])) return {};
        if (d[a] == 0.0) {
            if (o[a] < lo[a] || o[a] > hi[a]) return {};
            continue;
        }
        double t0 = (lo[a] - o[a]) / d[a], t1 = (hi[a] - o[a]) / d[a];
        if (t0 > t1) std::swap(t0, t1);
        tmin = std::max(tmin, t0);
        tmax = std::min(tmax, t1);
    }
    if (!(tmin <= tmax) || !std::isfinite(tmax)) return {};

    // Every t where the ray crosses a grid plane splits it into pieces that each lie in one cell.
    std::vector<double> cuts{tmin, tmax};
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0.0) continue;
        const double p0 = o[a] + tmin * d[a], p1 = o[a] + tmax * d[a];
        const double kLo = std::max(std::ceil(std::min(p0, p1)) - 1.0, 0.0);
        const double kHi = std::min(std::floor(std::max(p0, p1)) + 1.0, n[a] - 1.0);
        for (double k = kLo; k <= kHi; k += 1.0) {
            const double t = (k - o[a]) / d[a];
            if (t > tmin && t < tmax) cuts.push_back(t);
        }
    }
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());

    Walk walk{vol, o, d, opt.iso, std::max(opt.skipCrossings, 0) + 1, 0, false, 0, 0.0, {}};
    CellData cell{};
    std::optional<double> t;
    if (cuts.size() == 1) {
        // The ray only touches the box (an edge or corner): take the cell it would enter going forward.
        const glm::dvec3 p = o + tmin * d;
        std::array<uint32_t, 3> idx;
        for (int a = 0; a < 3; ++a)
            idx[size_t(a)] = cellAlong(d[a] < 0.0 ? std::ceil(p[a]) - 1.0 : p[a], n[size_t(a)]);
        t = walk.visit(idx, tmin, tmin, cell);
    }
    for (size_t s = 0; !t && s + 1 < cuts.size(); ++s) {
        // The midpoint is safely inside the piece, so its floor names the cell without rounding doubt.
        const glm::dvec3 p = o + 0.5 * (cuts[s] + cuts[s + 1]) * d;
        t = walk.visit({cellAlong(p.x, n[0]), cellAlong(p.y, n[1]), cellAlong(p.z, n[2])}, cuts[s],
                       cuts[s + 1], cell);
    }
    if (!t) return {};

    Hit h;
    h.hit = true;
    h.t = *t;
    h.cell = cell.idx;
    h.cellId = cell.idx[0] + uint64_t(n[0]) * (cell.idx[1] + uint64_t(n[1]) * cell.idx[2]);
    h.indexPos = o + *t * d;
    h.worldPos = ray.origin + *t * ray.dir;
    const glm::dvec3 local = h.indexPos - glm::dvec3(cell.idx[0], cell.idx[1], cell.idx[2]);
    h.value = trilinear(cell.raw, local);
    // Chain rule: ijk = mInv * (p - origin), so grad_p f = mInv^T grad_ijk f.
    h.gradient = glm::transpose(mInv) * trilinearGradient(cell.raw, local);
    return h;
}

Image render(const Volume& vol, const Camera& cam, int width, int height, const Options& opt) {
    Image img{width, height, std::vector<Hit>(size_t(std::max(width, 0)) * size_t(std::max(height, 0)))};
    std::atomic<int> nextRow{0};
    auto work = [&] {
        for (int y; (y = nextRow.fetch_add(1)) < height;)
            for (int x = 0; x < width; ++x)
                img.hits[size_t(y) * size_t(width) + size_t(x)] =
                    trace(vol, primaryRay(cam, width, height, x, y), opt);
    };
    const int threads = std::clamp(int(std::thread::hardware_concurrency()), 1, std::max(height, 1));
    std::vector<std::jthread> pool;
    for (int i = 1; i < threads; ++i) pool.emplace_back(work);
    work();
    return img;
}

} // namespace iso::oracle
