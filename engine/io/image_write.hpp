// Image outputs (PNG, NRRD) written atomically, and readers for them used in tests and comparisons.
// Images are row-major with x fastest and row 0 the top row.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace iso {

void writePng(const std::filesystem::path& path, int width, int height, const std::vector<uint8_t>& rgba8);
// RGBA8 pixels of any PNG (converted to 4 channels); InputError when it cannot be read.
std::vector<uint8_t> readPng(const std::filesystem::path& path, int& width, int& height);

// Attached raw little-endian NRRD0004 files: 2D "float", "uint32" or "uint64" images, or RGBA float
// images as a 3D array with sizes 4 W H.
void writeNrrd2D(const std::filesystem::path& path, int width, int height, const std::vector<float>& values);
void writeNrrd2D(const std::filesystem::path& path, int width, int height,
                 const std::vector<uint32_t>& values);
void writeNrrd2D(const std::filesystem::path& path, int width, int height,
                 const std::vector<uint64_t>& values);
void writeNrrdRgba(const std::filesystem::path& path, int width, int height, const std::vector<float>& rgba);

// A 2D NRRD image of type float, uint32 or uint64 (type holds one of those names), values widened.
struct Nrrd2D {
    int w = 0, h = 0;
    std::string type;
    std::vector<double> values;
};
Nrrd2D readNrrd2D(const std::filesystem::path& path);

} // namespace iso
