#include "io/io_util.hpp"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <new>
#include <random>
#include <system_error>

#ifdef _WIN32
#include <process.h>
#define ISO_GETPID _getpid
#else
#include <unistd.h>
#define ISO_GETPID getpid
#endif

namespace iso {

namespace fs = std::filesystem;

// Volume::data is defined as little-endian and handed to the GPU as is.
static_assert(std::endian::native == std::endian::little, "isoscope assumes a little-endian host");

namespace {

// zlib counts in 32-bit uInt, so large buffers go through it in pieces.
constexpr std::size_t kZChunk = std::size_t(1) << 30;

std::string errnoText() {
    return std::generic_category().message(errno);
}

} // namespace

void fail(const fs::path& file, const std::string& problem) {
    throw InputError(file.string() + ": " + problem);
}

std::vector<std::byte> readFileBytes(const fs::path& path) {
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (!fs::exists(st)) fail(path, "file not found");
    if (fs::is_directory(st)) fail(path, "is a directory, expected a file");
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) fail(path, "cannot open: " + errnoText());
    const std::streamoff size = in.tellg();
    if (size < 0) fail(path, "cannot determine the file size");
    std::vector<std::byte> bytes(static_cast<std::size_t>(size));
    in.seekg(0);
    in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(size));
    if (in.gcount() != std::streamsize(size)) fail(path, "read error: " + errnoText());
    return bytes;
}

bool isGzip(std::span<const std::byte> data) {
    return data.size() >= 2 && data[0] == std::byte{0x1f} && data[1] == std::byte{0x8b};
}

std::vector<std::byte> inflateAll(const std::byte* data, std::size_t size, std::size_t expectedBytes,
                                  const std::string& what, bool exact) {
    std::vector<std::byte> out(expectedBytes);
    z_stream zs{};
    if (inflateInit2(&zs, 15 + 32) != Z_OK) throw std::bad_alloc();
    struct End {
        z_stream* s;
        ~End() { inflateEnd(s); }
    } end{&zs};

    std::size_t inPos = 0, outPos = 0;
    std::byte spare{}; // once out is full, one more decoded byte would be excess data
    bool streamEnded = false;
    for (;;) {
        if (streamEnded) {
            // gzip allows concatenated members; other bytes after the stream are padding and ignored.
            if (inPos == size || !isGzip({data + inPos, size - inPos})) break;
            inflateReset(&zs);
            streamEnded = false;
        }
        const bool full = outPos == expectedBytes;
        if (full && !exact) break;
        const auto availIn = static_cast<uInt>(std::min(size - inPos, kZChunk));
        const auto availOut = full ? 1u : static_cast<uInt>(std::min(expectedBytes - outPos, kZChunk));
        zs.next_in = reinterpret_cast<Bytef*>(const_cast<std::byte*>(data + inPos));
        zs.avail_in = availIn;
        zs.next_out = reinterpret_cast<Bytef*>(full ? &spare : out.data() + outPos);
        zs.avail_out = availOut;
        const int rc = inflate(&zs, Z_NO_FLUSH);
        inPos += availIn - zs.avail_in;
        const std::size_t produced = availOut - zs.avail_out;
        if (full && produced > 0)
            throw InputError(what + ": compressed data holds more than the expected " +
                             std::to_string(expectedBytes) + " bytes (check sizes and type)");
        outPos += produced;
        if (rc == Z_STREAM_END) {
            streamEnded = true;
        } else if (rc == Z_BUF_ERROR) { // no progress possible: the input ran out
            if (outPos < expectedBytes) break;
            throw InputError(what + ": compressed data is truncated (the stream has no end)");
        } else if (rc == Z_MEM_ERROR) {
            throw std::bad_alloc();
        } else if (rc != Z_OK) {
            throw InputError(what +
                             ": corrupt compressed data (zlib: " + (zs.msg ? zs.msg : "unknown error") + ")");
        }
    }
    if (outPos < expectedBytes)
        throw InputError(what + ": truncated: compressed data decodes to " + std::to_string(outPos) +
                         " bytes, expected " + std::to_string(expectedBytes));
    return out;
}

std::vector<std::byte> gzipCompress(std::span<const std::byte> data) {
    z_stream zs{};
    if (deflateInit2(&zs, Z_DEFAULT_COMPRESSION, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
        throw std::bad_alloc();
    struct End {
        z_stream* s;
        ~End() { deflateEnd(s); }
    } end{&zs};
    std::vector<std::byte> out(deflateBound(&zs, uLong(data.size())) + 64);
    std::size_t inPos = 0, outPos = 0;
    for (int rc = Z_OK; rc != Z_STREAM_END;) {
        if (outPos == out.size()) out.resize(out.size() * 2);
        const auto availIn = static_cast<uInt>(std::min(data.size() - inPos, kZChunk));
        const auto availOut = static_cast<uInt>(std::min(out.size() - outPos, kZChunk));
        zs.next_in = reinterpret_cast<Bytef*>(const_cast<std::byte*>(data.data() + inPos));
        zs.avail_in = availIn;
        zs.next_out = reinterpret_cast<Bytef*>(out.data() + outPos);
        zs.avail_out = availOut;
        rc = deflate(&zs, inPos + availIn == data.size() ? Z_FINISH : Z_NO_FLUSH);
        if (rc == Z_STREAM_ERROR) throw std::runtime_error("gzip compression failed");
        inPos += availIn - zs.avail_in;
        outPos += availOut - zs.avail_out;
    }
    out.resize(outPos);
    return out;
}

void ensureParentDir(const fs::path& path) {
    const fs::path parent = path.parent_path();
    if (!parent.empty()) fs::create_directories(parent);
}

void writeFileAtomic(const fs::path& dst, const std::function<void(std::ostream&)>& write) {
    std::random_device rd;
    char suffix[48];
    std::snprintf(suffix, sizeof suffix, ".tmp-%ld-%08x", static_cast<long>(ISO_GETPID()), rd());
    fs::path tmp = dst;
    tmp += suffix;
    const auto attempt = [&]() -> std::string {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) return "cannot create " + tmp.filename().string() + ": " + errnoText();
        write(out);
        out.flush();
        if (!out) return "write error: " + errnoText();
        out.close();
        if (!out) return "close failed: " + errnoText();
        fs::rename(tmp, dst);
        return {};
    };
    std::string reason;
    try {
        reason = attempt();
    } catch (const std::exception& e) {
        reason = e.what();
    } catch (...) {
        reason = "unknown error";
    }
    if (reason.empty()) return;
    std::error_code ec;
    fs::remove(tmp, ec);
    throw std::runtime_error(dst.string() + ": cannot write: " + reason);
}

std::string toLower(std::string_view s) {
    std::string r(s);
    for (char& c : r) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return r;
}

std::string_view trim(std::string_view s) {
    const auto blank = [](char c) {
        return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
    };
    while (!s.empty() && blank(s.front())) s.remove_prefix(1);
    while (!s.empty() && blank(s.back())) s.remove_suffix(1);
    return s;
}

std::vector<std::string_view> splitWords(std::string_view s) {
    std::vector<std::string_view> words;
    std::size_t i = 0;
    while (i < s.size()) {
        while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
        const std::size_t start = i;
        while (i < s.size() && !std::isspace(static_cast<unsigned char>(s[i]))) ++i;
        if (i > start) words.push_back(s.substr(start, i - start));
    }
    return words;
}

bool nextLine(std::string_view text, std::size_t& pos, std::string_view& line) {
    if (pos >= text.size()) return false;
    const std::size_t nl = text.find('\n', pos);
    const std::size_t end = nl == std::string_view::npos ? text.size() : nl;
    line = text.substr(pos, end - pos);
    if (line.ends_with('\r')) line.remove_suffix(1);
    pos = nl == std::string_view::npos ? text.size() : nl + 1;
    return true;
}

std::optional<HeaderField> splitField(std::string_view line, char sep) {
    const std::size_t at = line.find(sep);
    if (at == std::string_view::npos) return std::nullopt;
    HeaderField f;
    for (char c : line.substr(0, at))
        if (!std::isspace(static_cast<unsigned char>(c)))
            f.key += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    f.value = trim(line.substr(at + 1));
    return f;
}

namespace {

// Words of a numeric field; NRRD writes vectors as "(x,y,z)", so brackets and commas separate too.
std::vector<std::string_view> numberWords(std::string_view text) {
    std::string_view rest = text;
    std::vector<std::string_view> words;
    while (!rest.empty()) {
        const std::size_t start = rest.find_first_not_of(" \t\r\n(),");
        if (start == std::string_view::npos) break;
        rest.remove_prefix(start);
        const std::size_t end = std::min(rest.find_first_of(" \t\r\n(),"), rest.size());
        words.push_back(rest.substr(0, end));
        rest.remove_prefix(end);
    }
    return words;
}

template <class T>
std::vector<T> parseList(const fs::path& file, std::string_view field, std::string_view text,
                         std::size_t count, const char* kind) {
    std::vector<T> values;
    for (std::string_view w : numberWords(text)) {
        std::string_view digits = w.starts_with('+') ? w.substr(1) : w;
        T value{};
        const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
        if (ec != std::errc() || end != digits.data() + digits.size() || digits.empty())
            fail(file, "field '" + std::string(field) + "': '" + std::string(w) + "' is not a valid " + kind);
        values.push_back(value);
    }
    if (count != 0 && values.size() != count)
        fail(file, "field '" + std::string(field) + "' needs " + std::to_string(count) + " " + kind +
                       "s, got '" + std::string(trim(text)) + "'");
    return values;
}

} // namespace

std::vector<double> parseNumbers(const fs::path& file, std::string_view field, std::string_view text,
                                 std::size_t count) {
    return parseList<double>(file, field, text, count, "number");
}

std::vector<int64_t> parseIntegers(const fs::path& file, std::string_view field, std::string_view text,
                                   std::size_t count) {
    return parseList<int64_t>(file, field, text, count, "integer");
}

std::size_t checkedSampleCount(const fs::path& file, std::span<const int64_t> sizes) {
    constexpr uint64_t kMaxSamples = uint64_t(1) << 40;
    std::string shape;
    for (int64_t s : sizes) shape += (shape.empty() ? "" : " x ") + std::to_string(s);
    uint64_t total = 1;
    for (std::size_t axis = 0; axis < sizes.size(); ++axis) {
        const int64_t s = sizes[axis];
        if (s <= 0)
            fail(file, "size " + std::to_string(s) + " of axis " + std::to_string(axis) + " is not positive");
        if (uint64_t(s) > std::numeric_limits<uint32_t>::max() || total > kMaxSamples / uint64_t(s))
            fail(file, "sizes " + shape + " are too large (at most 2^40 samples)");
        total *= uint64_t(s);
    }
    return static_cast<std::size_t>(total);
}

void checkSpacing(const fs::path& file, const glm::dvec3& spacing) {
    for (int a = 0; a < 3; ++a)
        if (!std::isfinite(spacing[a]) || spacing[a] <= 0.0)
            fail(file, "spacing " + std::to_string(spacing[a]) + " of axis " + std::to_string(a) +
                           " must be positive and finite");
}

glm::dvec3 splitAxes(const fs::path& file, const glm::dmat3& axes, glm::dmat3& directions) {
    glm::dvec3 lengths;
    for (int a = 0; a < 3; ++a) {
        lengths[a] = glm::length(axes[a]);
        if (!std::isfinite(lengths[a]) || lengths[a] <= 0.0)
            fail(file, "the direction of axis " + std::to_string(a) + " is zero or not finite");
        directions[a] = axes[a] / lengths[a];
    }
    // Parallel axes would make the grid flat and world-to-index mapping impossible.
    if (std::abs(glm::determinant(directions)) < 1e-6)
        fail(file, "the axis directions are degenerate (parallel)");
    return lengths;
}

fs::path findDataFile(const fs::path& header, std::string_view name) {
    const fs::path file(name);
    const fs::path resolved = file.is_absolute() ? file : header.parent_path() / file;
    std::error_code ec;
    if (!fs::is_regular_file(resolved, ec))
        fail(header, "data file '" + std::string(name) + "' not found next to the header (looked for " +
                         fs::absolute(resolved, ec).lexically_normal().string() + ")");
    return resolved;
}

void swapBytes(std::byte* data, std::size_t count, std::size_t width) {
    if (width < 2) return;
    for (std::size_t i = 0; i < count; ++i) std::reverse(data + i * width, data + (i + 1) * width);
}

std::vector<std::byte> extractPayload(const fs::path& file, std::vector<std::byte>&& bytes,
                                      std::size_t offset, int64_t skip, bool compressed, std::size_t expected,
                                      bool exact) {
    offset = std::min(offset, bytes.size());
    std::size_t avail = bytes.size() - offset;
    if (skip < -1) fail(file, "byte skip " + std::to_string(skip) + " is invalid (use -1 or a count >= 0)");
    if (compressed) {
        if (skip < 0) fail(file, "byte skip -1 cannot be used with compressed data");
        const auto skipped = static_cast<std::size_t>(skip);
        std::vector<std::byte> out =
            inflateAll(bytes.data() + offset, avail, expected + skipped, file.string(), exact);
        out.erase(out.begin(), out.begin() + std::ptrdiff_t(skipped));
        return out;
    }
    if (skip == -1) {
        if (avail > expected) offset += avail - expected;
        avail = std::min(avail, expected);
    } else if (uint64_t(skip) > avail) {
        fail(file, "byte skip " + std::to_string(skip) + " is beyond the end of the data (" +
                       std::to_string(avail) + " bytes)");
    } else {
        offset += std::size_t(skip);
        avail -= std::size_t(skip);
    }
    if (avail < expected)
        fail(file,
             "truncated: data has " + std::to_string(avail) + " bytes, expected " + std::to_string(expected));
    if (exact && avail > expected)
        fail(file, "data has " + std::to_string(avail) + " bytes, expected " + std::to_string(expected) +
                       " (check sizes, type and byte skip)");
    bytes.erase(bytes.begin(), bytes.begin() + std::ptrdiff_t(offset));
    bytes.resize(expected);
    return std::move(bytes);
}

void finishVolume(Volume& v, const fs::path& path, std::vector<std::byte>&& payload, bool bigEndian) {
    v.data = std::move(payload);
    if (bigEndian) swapBytes(v.data.data(), v.sampleCount(), voxelBytes(v.type));
    v.source = path.string();
    v.computeRange();
}

} // namespace iso
