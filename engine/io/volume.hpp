// A scalar volume as read from a scan: samples on a regular grid, with the scan's geometry.
#pragma once

#include <glm/glm.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace iso {

enum class VoxelType : uint8_t { U8, I16, U16, F32 };

std::size_t voxelBytes(VoxelType t);
const char* voxelTypeName(VoxelType t);                        // "u8", "i16", "u16", "f32"
std::optional<VoxelType> parseVoxelType(const std::string& s); // accepts u8/uint8/uchar, i16/int16/short, ...

// World position of sample (i,j,k) = origin + directions * (spacing * (i,j,k)).
// directions holds unit column vectors in LPS patient space (NRRD and MetaImage are
// LPS already; NIfTI's RAS is flipped on load), so physical coordinates agree across formats.
struct Volume {
    std::array<uint32_t, 3> dims{0, 0, 0}; // samples along i, j, k; i varies fastest in `data`
    glm::dvec3 spacing{1.0};
    glm::dvec3 origin{0.0};
    glm::dmat3 directions{1.0};
    VoxelType type = VoxelType::U8;
    std::vector<std::byte> data; // native (little-endian) byte order, dims product * voxelBytes(type)
    double valueMin = 0.0, valueMax = 0.0; // over finite samples
    std::string source;                    // path it was read from, for messages

    std::size_t sampleCount() const { return std::size_t(dims[0]) * dims[1] * dims[2]; }
    std::size_t byteSize() const { return sampleCount() * voxelBytes(type); }
    std::size_t index(uint32_t i, uint32_t j, uint32_t k) const {
        return i + std::size_t(dims[0]) * (j + std::size_t(dims[1]) * k);
    }
    double value(uint32_t i, uint32_t j, uint32_t k) const; // the stored value, in the scan's units
    glm::dvec3 worldOf(const glm::dvec3& ijk) const { return origin + directions * (spacing * ijk); }
    void computeRange(); // sets valueMin/valueMax from data
};

// A problem with an input file: what() is one line that names the file and what is wrong.
struct InputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// For headerless raw files the geometry comes from the command line.
struct RawLayout {
    std::array<uint32_t, 3> dims{0, 0, 0};
    VoxelType type = VoxelType::U8;
    glm::dvec3 spacing{1.0};
    bool bigEndian = false;
};

// Counts of finite samples in `counts.size()` equal-width bins over [lo, hi] = [valueMin, valueMax];
// values outside (a stale range) land in the end bins.
struct Histogram {
    double lo = 0.0, hi = 0.0;
    std::vector<uint64_t> counts;
};
Histogram histogram(const Volume& v, int bins);

// Reads NRRD (.nrrd/.nhdr), MetaImage (.mhd/.mha), NIfTI (.nii/.nii.gz), or raw (with `raw`).
// Throws InputError for anything malformed; never returns a partial volume.
Volume loadVolume(const std::filesystem::path& path, const std::optional<RawLayout>& raw = std::nullopt);

} // namespace iso
