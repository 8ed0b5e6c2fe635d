#include "io/image_write.hpp"
#include "io/io_util.hpp"

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

#include <climits>
#include <initializer_list>
#include <memory>
#include <ostream>
#include <stdexcept>

namespace iso {

namespace fs = std::filesystem;

namespace {

void checkSize(const char* what, int width, int height, std::size_t have, std::size_t perPixel) {
    if (width <= 0 || height <= 0 || have != std::size_t(width) * std::size_t(height) * perPixel)
        throw std::invalid_argument(std::string(what) + ": " + std::to_string(have) + " values do not fit " +
                                    std::to_string(width) + "x" + std::to_string(height) + "x" +
                                    std::to_string(perPixel));
}

template <class T>
void writeNrrd(const fs::path& path, const char* type, std::initializer_list<int> sizes,
               const std::vector<T>& values) {
    writeFileAtomic(path, [&](std::ostream& out) {
        out << "NRRD0004\ntype: " << type << "\ndimension: " << sizes.size() << "\nsizes:";
        for (int s : sizes) out << ' ' << s;
        out << "\nencoding: raw\nendian: little\n\n";
        out.write(reinterpret_cast<const char*>(values.data()), std::streamsize(values.size() * sizeof(T)));
    });
}

} // namespace

void writePng(const fs::path& path, int width, int height, const std::vector<uint8_t>& rgba8) {
    checkSize("writePng", width, height, rgba8.size(), 4);
    std::vector<char> png;
    const auto append = [](void* context, void* data, int size) {
        auto* buffer = static_cast<std::vector<char>*>(context);
        buffer->insert(buffer->end(), static_cast<char*>(data), static_cast<char*>(data) + size);
    };
    if (!stbi_write_png_to_func(append, &png, width, height, 4, rgba8.data(), width * 4))
        throw std::runtime_error(path.string() + ": cannot write: PNG encoding failed");
    writeFileAtomic(path, [&](std::ostream& out) { out.write(png.data(), std::streamsize(png.size())); });
}

std::vector<uint8_t> readPng(const fs::path& path, int& width, int& height) {
    const std::vector<std::byte> bytes = readFileBytes(path);
    if (bytes.size() > std::size_t(INT_MAX)) fail(path, "file is too large for a PNG");
    int channels = 0;
    const std::unique_ptr<stbi_uc, void (*)(void*)> pixels(
        stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()), int(bytes.size()), &width,
                              &height, &channels, 4),
        stbi_image_free);
    if (!pixels) fail(path, std::string("cannot read as PNG: ") + stbi_failure_reason());
    return {pixels.get(), pixels.get() + std::size_t(width) * std::size_t(height) * 4};
}

void writeNrrd2D(const fs::path& path, int width, int height, const std::vector<float>& values) {
    checkSize("writeNrrd2D", width, height, values.size(), 1);
    writeNrrd(path, "float", {width, height}, values);
}

void writeNrrd2D(const fs::path& path, int width, int height, const std::vector<uint32_t>& values) {
    checkSize("writeNrrd2D", width, height, values.size(), 1);
    writeNrrd(path, "uint32", {width, height}, values);
}

void writeNrrd2D(const fs::path& path, int width, int height, const std::vector<uint64_t>& values) {
    checkSize("writeNrrd2D", width, height, values.size(), 1);
    writeNrrd(path, "uint64", {width, height}, values);
}

void writeNrrdRgba(const fs::path& path, int width, int height, const std::vector<float>& rgba) {
    checkSize("writeNrrdRgba", width, height, rgba.size(), 4);
    writeNrrd(path, "float", {4, width, height}, rgba);
}

} // namespace iso
