#include "io/volume.hpp"
#include "io/io_util.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace iso {

namespace {

// memcpy rather than a cast: data is a byte buffer, not an array of T.
template <class T>
T load(const std::byte* p) {
    T t;
    std::memcpy(&t, p, sizeof t);
    return t;
}

template <class F>
void forEachSample(const Volume& v, F&& f) {
    const std::byte* p = v.data.data();
    const std::size_t n = std::min(v.sampleCount(), v.data.size() / voxelBytes(v.type));
    const auto run = [&]<class T>(T) {
        for (std::size_t i = 0; i < n; ++i) f(double(load<T>(p + i * sizeof(T))));
    };
    switch (v.type) {
    case VoxelType::U8:
        run(uint8_t{});
        break;
    case VoxelType::I16:
        run(int16_t{});
        break;
    case VoxelType::U16:
        run(uint16_t{});
        break;
    case VoxelType::F32:
        run(float{});
        break;
    }
}

} // namespace

std::size_t voxelBytes(VoxelType t) {
    switch (t) {
    case VoxelType::U8:
        return 1;
    case VoxelType::I16:
    case VoxelType::U16:
        return 2;
    case VoxelType::F32:
        return 4;
    }
    return 1;
}

const char* voxelTypeName(VoxelType t) {
    switch (t) {
    case VoxelType::U8:
        return "u8";
    case VoxelType::I16:
        return "i16";
    case VoxelType::U16:
        return "u16";
    case VoxelType::F32:
        return "f32";
    }
    return "?";
}

std::optional<VoxelType> parseVoxelType(const std::string& s) {
    const std::string t = toLower(s);
    if (t == "u8" || t == "uint8" || t == "uint8_t" || t == "uchar") return VoxelType::U8;
    if (t == "i16" || t == "int16" || t == "int16_t" || t == "short") return VoxelType::I16;
    if (t == "u16" || t == "uint16" || t == "uint16_t" || t == "ushort") return VoxelType::U16;
    if (t == "f32" || t == "float" || t == "float32") return VoxelType::F32;
    return std::nullopt;
}

double sampleAt(const Volume& v, std::size_t index) {
    const std::byte* p = v.data.data() + index * voxelBytes(v.type);
    switch (v.type) {
    case VoxelType::U8:
        return load<uint8_t>(p);
    case VoxelType::I16:
        return load<int16_t>(p);
    case VoxelType::U16:
        return load<uint16_t>(p);
    case VoxelType::F32:
        return load<float>(p);
    }
    return 0.0;
}

double Volume::value(uint32_t i, uint32_t j, uint32_t k) const {
    return sampleAt(*this, index(i, j, k));
}

void Volume::computeRange() {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    forEachSample(*this, [&](double x) {
        if (std::isfinite(x)) {
            lo = std::min(lo, x);
            hi = std::max(hi, x);
        }
    });
    if (lo > hi) lo = hi = 0.0; // no finite sample at all
    valueMin = lo;
    valueMax = hi;
}

Histogram histogram(const Volume& v, int bins) {
    if (bins <= 0) throw std::invalid_argument("histogram: bins must be positive");
    Histogram h{v.valueMin, v.valueMax, std::vector<uint64_t>(std::size_t(bins), 0)};
    const double scale = h.hi > h.lo ? bins / (h.hi - h.lo) : 0.0;
    const auto last = static_cast<double>(bins - 1);
    forEachSample(v, [&](double x) {
        if (std::isfinite(x)) ++h.counts[std::size_t(std::clamp((x - h.lo) * scale, 0.0, last))];
    });
    return h;
}

} // namespace iso
