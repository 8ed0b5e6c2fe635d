#include "oracle/analytic.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace iso::analytic {

namespace {

template <class T>
void putAs(std::byte* dst, double v) {
    T x;
    if constexpr (std::is_floating_point_v<T>) {
        x = T(v);
    } else {
        x = T(std::clamp(std::round(v), double(std::numeric_limits<T>::min()),
                         double(std::numeric_limits<T>::max())));
    }
    std::memcpy(dst, &x, sizeof x);
}

void put(Volume& vol, std::size_t index, double v) {
    std::byte* dst = vol.data.data() + index * voxelBytes(vol.type);
    switch (vol.type) {
    case VoxelType::U8:
        putAs<uint8_t>(dst, v);
        break;
    case VoxelType::I16:
        putAs<int16_t>(dst, v);
        break;
    case VoxelType::U16:
        putAs<uint16_t>(dst, v);
        break;
    case VoxelType::F32:
        putAs<float>(dst, v);
        break;
    }
}

Volume geometry(std::array<uint32_t, 3> dims, VoxelType type) {
    if (dims[0] == 0 || dims[1] == 0 || dims[2] == 0)
        throw std::invalid_argument("analytic volume: empty dims");
    Volume v;
    v.dims = dims;
    v.type = type;
    v.source = "analytic";
    return v;
}

uint32_t checkedN(int n) {
    if (n < 1) throw std::invalid_argument("analytic volume: n must be >= 1");
    return uint32_t(n);
}

// Fills vol with f(world position) stored as (f + offset) * scale.
void fill(Volume& vol, const std::function<double(const glm::dvec3&)>& f, double offset, double scale) {
    vol.data.assign(vol.byteSize(), std::byte{0});
    for (uint32_t k = 0; k < vol.dims[2]; ++k)
        for (uint32_t j = 0; j < vol.dims[1]; ++j)
            for (uint32_t i = 0; i < vol.dims[0]; ++i)
                put(vol, vol.index(i, j, k), (f(vol.worldOf(glm::dvec3(i, j, k))) + offset) * scale);
    vol.computeRange();
}

SphereScene sphereOn(Volume vol, double radius) {
    SphereScene s;
    s.centre = vol.worldOf((glm::dvec3(vol.dims[0], vol.dims[1], vol.dims[2]) - 1.0) / 2.0);
    s.radius = radius;
    const auto f = [&](const glm::dvec3& p) { return radius - glm::length(p - s.centre); };
    if (vol.type != VoxelType::F32) {
        // Span the whole integer range: f is largest at the centre sample and smallest at a corner.
        double fmin = std::numeric_limits<double>::infinity(), fmax = -fmin;
        for (int c = 0; c < 8; ++c) {
            glm::dvec3 ijk;
            for (int a = 0; a < 3; ++a) ijk[a] = (c >> a & 1) ? vol.dims[size_t(a)] - 1.0 : 0.0;
            fmin = std::min(fmin, f(vol.worldOf(ijk)));
        }
        for (uint32_t k = 0; k < vol.dims[2]; ++k)
            for (uint32_t j = 0; j < vol.dims[1]; ++j)
                for (uint32_t i = 0; i < vol.dims[0]; ++i)
                    fmax = std::max(fmax, f(vol.worldOf(glm::dvec3(i, j, k))));
        double lo = 0.0, hi = 0.0;
        switch (vol.type) {
        case VoxelType::U8:
            hi = 255.0;
            break;
        case VoxelType::I16:
            lo = -32768.0, hi = 32767.0;
            break;
        case VoxelType::U16:
            hi = 65535.0;
            break;
        case VoxelType::F32:
            break;
        }
        if (fmax > fmin) {
            s.scale = (hi - lo) / (fmax - fmin);
            s.offset = lo / s.scale - fmin;
        } else {
            s.offset = lo - fmin; // one value only: put it at the bottom of the range
        }
    }
    fill(vol, f, s.offset, s.scale);
    s.iso = s.offset * s.scale;
    s.vol = std::move(vol);
    return s;
}

} // namespace

SphereScene sphereDistance(int n, double radius, glm::dvec3 spacing, VoxelType type) {
    const uint32_t m = checkedN(n);
    Volume vol = geometry({m, m, m}, type);
    vol.spacing = spacing;
    return sphereOn(std::move(vol), radius);
}

SphereScene sphereAnisotropic(int n, double radius, VoxelType type) {
    const uint32_t m = checkedN(n);
    Volume vol = geometry({m, m, m}, type);
    vol.spacing = {0.8, 1.3, 2.0};
    const double a = std::numbers::pi / 6.0;
    vol.directions = glm::dmat3(glm::dvec3(std::cos(a), std::sin(a), 0.0),
                                glm::dvec3(-std::sin(a), std::cos(a), 0.0), glm::dvec3(0.0, 0.0, 1.0));
    vol.origin = {-12.5, 30.0, 7.0};
    return sphereOn(std::move(vol), radius);
}

SphereScene sphereU16(int n, double radius) {
    return sphereDistance(n, radius, {1.0, 1.0, 1.0}, VoxelType::U16);
}

double analyticSphereT(const Ray& ray, const glm::dvec3& centre, double radius) {
    // |o + t d - c|^2 = r^2 with |d| = 1: t^2 + 2 b t + c = 0.
    const glm::dvec3 oc = ray.origin - centre;
    const double b = glm::dot(oc, ray.dir), c = glm::dot(oc, oc) - radius * radius;
    const double disc = b * b - c;
    if (disc < 0.0) return -1.0;
    const double s = std::sqrt(disc);
    if (-b - s >= 0.0) return -b - s;
    if (-b + s >= 0.0) return -b + s;
    return -1.0;
}

Scene marschnerLobb(int n) {
    const uint32_t m = checkedN(n);
    if (m < 2) throw std::invalid_argument("marschnerLobb: n must be >= 2");
    Scene s{geometry({m, m, m}, VoxelType::F32), 0.5};
    s.vol.spacing = glm::dvec3(2.0 / (m - 1.0));
    s.vol.origin = glm::dvec3(-1.0);
    constexpr double fM = 6.0, alpha = 0.25, pi = std::numbers::pi;
    const auto f = [](const glm::dvec3& p) {
        const double rhoR = std::cos(2.0 * pi * fM * std::cos(pi * std::hypot(p.x, p.y) / 2.0));
        return (1.0 - std::sin(pi * p.z / 2.0) + alpha * (1.0 + rhoR)) / (2.0 * (1.0 + alpha));
    };
    fill(s.vol, f, 0.0, 1.0);
    return s;
}

Volume linearRamp(std::array<uint32_t, 3> dims, glm::dvec3 gradient, VoxelType type) {
    Volume vol = geometry(dims, type);
    fill(
        vol, [&](const glm::dvec3& p) { return glm::dot(gradient, p); }, 0.0, 1.0);
    return vol;
}

ShellScene nestedShells(int n, std::array<double, 3> radii) {
    const uint32_t m = checkedN(n);
    std::sort(radii.begin(), radii.end());
    ShellScene s{geometry({m, m, m}, VoxelType::F32), 0.0, glm::dvec3((m - 1.0) / 2.0), radii};
    const double norm = radii[2] * radii[2] * radii[2];
    const auto f = [&](const glm::dvec3& p) {
        const double r = glm::length(p - s.centre);
        return -(r - radii[0]) * (r - radii[1]) * (r - radii[2]) / (norm != 0.0 ? norm : 1.0);
    };
    fill(s.vol, f, 0.0, 1.0);
    return s;
}

} // namespace iso::analytic
