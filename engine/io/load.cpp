#include "io/io_util.hpp"
#include "io/volume.hpp"

#include <new>

namespace iso {

namespace fs = std::filesystem;

Volume loadVolume(const fs::path& path, const std::optional<RawLayout>& raw) {
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (!fs::exists(st)) fail(path, "file not found");
    if (fs::is_directory(st))
        fail(path, "is a directory; give the volume file itself (.nrrd, .nhdr, .mhd, ...)");
    if (fs::is_regular_file(st) && fs::file_size(path, ec) == 0) fail(path, "file is empty");

    const std::string name = toLower(path.filename().string());
    try {
        // Explicit raw geometry wins: raw files come with any extension (.raw, .img, .dat, ...).
        if (raw) return loadRaw(path, *raw);
        if (name.ends_with(".nrrd") || name.ends_with(".nhdr")) return loadNrrd(path);
        if (name.ends_with(".mhd") || name.ends_with(".mha")) return loadMetaImage(path);
        if (name.ends_with(".nii") || name.ends_with(".nii.gz")) return loadNifti(path);
    } catch (const std::bad_alloc&) {
        fail(path, "out of memory while reading the volume (are the sizes in the header right?)");
    } catch (const std::length_error&) {
        fail(path, "out of memory while reading the volume (are the sizes in the header right?)");
    }
    fail(path, "unknown file type (supported: .nrrd, .nhdr, .mhd, .mha, .nii, .nii.gz; "
               "for headerless raw data give --raw-dims and --raw-type)");
}

Volume loadRaw(const fs::path& path, const RawLayout& layout) {
    const std::array<int64_t, 3> sizes{layout.dims[0], layout.dims[1], layout.dims[2]};
    const std::size_t expected = checkedSampleCount(path, sizes) * voxelBytes(layout.type);
    checkSpacing(path, layout.spacing);
    Volume v;
    v.dims = layout.dims;
    v.type = layout.type;
    v.spacing = layout.spacing;
    std::vector<std::byte> bytes = readFileBytes(path);
    const bool gz = isGzip(bytes);
    if (!gz && bytes.size() != expected)
        fail(path, "has " + std::to_string(bytes.size()) + " bytes, expected " + std::to_string(expected) +
                       " for " + std::to_string(sizes[0]) + "x" + std::to_string(sizes[1]) + "x" +
                       std::to_string(sizes[2]) + " " + voxelTypeName(layout.type) +
                       " (check --raw-dims and --raw-type)");
    finishVolume(v, path, extractPayload(path, std::move(bytes), 0, 0, gz, expected), layout.bigEndian);
    return v;
}

} // namespace iso
