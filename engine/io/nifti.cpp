#include "io/io_util.hpp"

#include <cmath>
#include <cstring>

namespace iso {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kHeaderBytes = 348;

std::string datatypeName(int code) {
    switch (code) {
    case 1:
        return "binary";
    case 8:
        return "int32";
    case 32:
        return "complex64";
    case 64:
        return "float64";
    case 128:
        return "rgb24";
    case 256:
        return "int8";
    case 768:
        return "uint32";
    case 1024:
        return "int64";
    case 1280:
        return "uint64";
    case 2304:
        return "rgba32";
    default:
        return "unknown";
    }
}

} // namespace

Volume loadNifti(const fs::path& path) {
    std::vector<std::byte> bytes = readFileBytes(path);
    const bool gz = isGzip(bytes);
    const std::vector<std::byte> hdr =
        gz ? inflateAll(bytes.data(), bytes.size(), kHeaderBytes, path.string(), false)
           : std::vector<std::byte>(bytes.begin(),
                                    bytes.begin() + std::ptrdiff_t(std::min(bytes.size(), kHeaderBytes)));
    if (hdr.size() < kHeaderBytes)
        fail(path, "too short for a NIfTI-1 header (" + std::to_string(hdr.size()) + " bytes, need 348)");

    // sizeof_hdr is 348 in the writer's byte order, which tells us whether to swap everything.
    int32_t sizeofHdr;
    std::memcpy(&sizeofHdr, hdr.data(), 4);
    int32_t swapped = sizeofHdr;
    swapBytes(reinterpret_cast<std::byte*>(&swapped), 1, 4);
    if (sizeofHdr == 540 || swapped == 540)
        fail(path, "NIfTI-2 is not supported; save the scan as NIfTI-1, NRRD or MetaImage");
    if (sizeofHdr != 348 && swapped != 348)
        fail(path, "not a NIfTI-1 file (the header size field is not 348)");
    const bool swap = sizeofHdr != 348;
    const auto get = [&]<class T>(std::size_t offset, T) {
        T value;
        std::memcpy(&value, hdr.data() + offset, sizeof(T));
        if (swap) swapBytes(reinterpret_cast<std::byte*>(&value), 1, sizeof(T));
        return value;
    };
    const auto f32 = [&](std::size_t offset) { return double(get(offset, float{})); };
    const auto i16 = [&](std::size_t offset) { return get(offset, int16_t{}); };

    const std::string_view magic(reinterpret_cast<const char*>(hdr.data()) + 344, 4);
    if (magic == std::string_view("ni1\0", 4))
        fail(path, "is the header of a .hdr/.img pair; only single-file NIfTI (.nii, .nii.gz) is supported");
    if (magic != std::string_view("n+1\0", 4)) fail(path, "not a NIfTI-1 file (bad magic, expected 'n+1')");

    const int ndim = i16(40);
    if (ndim < 3 || ndim > 7) fail(path, "has " + std::to_string(ndim) + " dimensions, expected a 3D volume");
    for (int d = 4; d <= ndim; ++d)
        if (i16(40 + 2 * std::size_t(d)) > 1)
            fail(path, "holds several volumes (dim[" + std::to_string(d) +
                           "] = " + std::to_string(i16(40 + 2 * std::size_t(d))) +
                           "); only a single 3D volume is supported");
    const std::array<int64_t, 3> sizes{i16(42), i16(44), i16(46)};
    const std::size_t count = checkedSampleCount(path, sizes);

    Volume v;
    for (int a = 0; a < 3; ++a) v.dims[a] = uint32_t(sizes[a]);
    const int datatype = i16(70);
    switch (datatype) {
    case 2:
        v.type = VoxelType::U8;
        break;
    case 4:
        v.type = VoxelType::I16;
        break;
    case 512:
        v.type = VoxelType::U16;
        break;
    case 16:
        v.type = VoxelType::F32;
        break;
    default:
        fail(path, "unsupported datatype " + std::to_string(datatype) + " (" + datatypeName(datatype) +
                       "); supported: uint8 (2), int16 (4), uint16 (512), float32 (16)");
    }

    const double voxOffset = f32(108);
    if (!std::isfinite(voxOffset) || voxOffset < double(kHeaderBytes) || voxOffset > 1e12)
        fail(path, "invalid vox_offset " + std::to_string(voxOffset));
    const auto offset = static_cast<std::size_t>(voxOffset);
    const std::size_t expected = count * voxelBytes(v.type);
    // Extra bytes after the voxels are tolerated: NIfTI does not forbid padding.
    if (gz) bytes = inflateAll(bytes.data(), bytes.size(), offset + expected, path.string(), false);
    std::vector<std::byte> payload =
        extractPayload(path, std::move(bytes), offset, 0, false, expected, false);

    // Affine from voxel index to RAS: sform if set, else the qform quaternion, else pixdim alone.
    glm::dmat3 axes(1.0);
    glm::dvec3 origin(0.0);
    const glm::dvec3 pixdim(f32(80), f32(84), f32(88));
    if (i16(254) > 0) {
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) axes[c][r] = f32(280 + 16 * std::size_t(r) + 4 * std::size_t(c));
            origin[r] = f32(280 + 16 * std::size_t(r) + 12);
        }
    } else if (i16(252) > 0) {
        const double b = f32(256), c = f32(260), d = f32(264);
        const double a = std::sqrt(std::max(0.0, 1.0 - (b * b + c * c + d * d)));
        const glm::dmat3 rot(a * a + b * b - c * c - d * d, 2 * (b * c + a * d), 2 * (b * d - a * c),
                             2 * (b * c - a * d), a * a + c * c - b * b - d * d, 2 * (c * d + a * b),
                             2 * (b * d + a * c), 2 * (c * d - a * b), a * a + d * d - b * b - c * c);
        const double qfac = f32(76) < 0.0 ? -1.0 : 1.0;
        axes = rot * glm::dmat3(glm::dvec3(pixdim.x, 0, 0), glm::dvec3(0, pixdim.y, 0),
                                glm::dvec3(0, 0, pixdim.z * qfac));
        origin = glm::dvec3(f32(268), f32(272), f32(276));
    } else {
        axes = glm::dmat3(glm::dvec3(pixdim.x, 0, 0), glm::dvec3(0, pixdim.y, 0), glm::dvec3(0, 0, pixdim.z));
    }
    const glm::dmat3 rasToLps(glm::dvec3(-1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 1));
    v.spacing = splitAxes(path, rasToLps * axes, v.directions);
    v.origin = rasToLps * origin;
    checkSpacing(path, v.spacing);

    finishVolume(v, path, std::move(payload), swap);
    const double slope = f32(112), inter = f32(116);
    if (std::isfinite(slope) && std::isfinite(inter) && slope != 0.0 && !(slope == 1.0 && inter == 0.0)) {
        // Scaled values are what the scan means (e.g. Hounsfield units), so store them as floats.
        std::vector<std::byte> scaled(count * sizeof(float));
        for (std::size_t i = 0; i < count; ++i) {
            const auto x = static_cast<float>(sampleAt(v, i) * slope + inter);
            std::memcpy(scaled.data() + i * sizeof(float), &x, sizeof(float));
        }
        v.type = VoxelType::F32;
        v.data = std::move(scaled);
        v.computeRange();
    }
    return v;
}

} // namespace iso
