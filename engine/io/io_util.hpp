// File and parsing helpers shared by the volume readers and the image writers.
#pragma once

#include "io/volume.hpp"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace iso {

// Whole file; InputError when it is missing, a directory or unreadable. An empty file is not an error here.
std::vector<std::byte> readFileBytes(const std::filesystem::path& path);

// Inflates a zlib or gzip stream (concatenated gzip members too) into exactly expectedBytes.
// InputError "<what>: ..." when the data is corrupt, ends early, or, with exact, holds more than that.
std::vector<std::byte> inflateAll(const std::byte* data, std::size_t size, std::size_t expectedBytes,
                                  const std::string& what, bool exact = true);
// A single gzip member at the default level.
std::vector<std::byte> gzipCompress(std::span<const std::byte> data);
bool isGzip(std::span<const std::byte> data);

// Writes through a temporary file next to dst and renames it into place, so dst is either the old file
// or the complete new one. Throws std::runtime_error("<dst>: cannot write: <reason>").
void writeFileAtomic(const std::filesystem::path& dst, const std::function<void(std::ostream&)>& write);
void ensureParentDir(const std::filesystem::path& path);

// ---- shared by the readers (internal to io/) ----

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& problem);

std::string toLower(std::string_view s);
std::string_view trim(std::string_view s);
std::vector<std::string_view> splitWords(std::string_view s); // on whitespace
// Next line of text at pos (without "\n" or "\r\n"); false at the end.
bool nextLine(std::string_view text, std::size_t& pos, std::string_view& line);
// "key<sep>value" with the key lowercased and stripped of blanks (so "data file" == "datafile").
struct HeaderField {
    std::string key;
    std::string_view value;
};
std::optional<HeaderField> splitField(std::string_view line, char sep);

// Exactly `count` numbers (count 0: any number) from the words of text; otherwise InputError naming the
// field.
std::vector<double> parseNumbers(const std::filesystem::path& file, std::string_view field,
                                 std::string_view text, std::size_t count = 0);
std::vector<int64_t> parseIntegers(const std::filesystem::path& file, std::string_view field,
                                   std::string_view text, std::size_t count);

// Sample count of a grid as read from a header; InputError unless every size is positive and fits
// uint32 and the total stays within 2^40 samples (checked before anything is allocated).
std::size_t checkedSampleCount(const std::filesystem::path& file, std::span<const int64_t> sizes);
void checkSpacing(const std::filesystem::path& file, const glm::dvec3& spacing);
// Normalises the columns of `axes` into directions and returns their lengths (the spacings).
glm::dvec3 splitAxes(const std::filesystem::path& file, const glm::dmat3& axes, glm::dmat3& directions);

// A detached data file named in `header`, resolved against the header's folder; InputError naming both
// when it is not there.
std::filesystem::path findDataFile(const std::filesystem::path& header, std::string_view name);

void swapBytes(std::byte* data, std::size_t count, std::size_t width);

// The `expected` payload bytes of a file read whole: from `offset`, then past `skip` further bytes
// (-1: the payload is the last `expected` bytes; for compressed data the skip counts decoded bytes).
// Messages name `file`; with exact, data beyond the payload is an error too.
std::vector<std::byte> extractPayload(const std::filesystem::path& file, std::vector<std::byte>&& bytes,
                                      std::size_t offset, int64_t skip, bool compressed, std::size_t expected,
                                      bool exact = true);

double sampleAt(const Volume& v, std::size_t index);
// Takes over the payload as v.data (swapped to native order), sets the value range and the source.
void finishVolume(Volume& v, const std::filesystem::path& path, std::vector<std::byte>&& payload,
                  bool bigEndian);

Volume loadNrrd(const std::filesystem::path& path);
Volume loadMetaImage(const std::filesystem::path& path);
Volume loadNifti(const std::filesystem::path& path);
Volume loadRaw(const std::filesystem::path& path, const RawLayout& layout);

} // namespace iso
