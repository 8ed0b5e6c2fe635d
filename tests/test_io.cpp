// Loaders and writers in engine/io, on small files written into a fresh temporary folder per test.
#include "io/image_write.hpp"
#include "io/io_util.hpp"
#include "io/volume.hpp"

#include "temp_dir.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <iterator>
#include <random>
#include <string>

namespace fs = std::filesystem;
using namespace iso;

namespace {

using Bytes = std::vector<std::byte>;

Bytes bytesOf(std::string_view s) {
    Bytes b(s.size());
    if (!s.empty()) std::memcpy(b.data(), s.data(), s.size());
    return b;
}

template <class T>
Bytes bytesOf(const std::vector<T>& values, bool bigEndian = false) {
    Bytes b(values.size() * sizeof(T));
    std::memcpy(b.data(), values.data(), b.size());
    if (bigEndian) swapBytes(b.data(), values.size(), sizeof(T));
    return b;
}

Bytes operator+(Bytes a, const Bytes& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

void writeFile(const fs::path& path, const Bytes& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    REQUIRE(out.good());
}

void writeText(const fs::path& path, std::string_view text) {
    writeFile(path, bytesOf(text));
}

// A zlib stream of stored (uncompressed) blocks, as MetaImage writers produce with zlib rather than gzip.
Bytes zlibStored(const Bytes& data) {
    REQUIRE(data.size() < 65536);
    const auto n = static_cast<uint16_t>(data.size());
    Bytes z{std::byte{0x78}, std::byte{0x01}, std::byte{0x01}};
    for (uint16_t v : {n, uint16_t(~n)}) z.insert(z.end(), {std::byte(v & 0xff), std::byte(v >> 8)});
    z.insert(z.end(), data.begin(), data.end());
    uint32_t a = 1, b = 0;
    for (std::byte x : data) {
        a = (a + uint32_t(x)) % 65521;
        b = (b + a) % 65521;
    }
    const uint32_t adler = (b << 16) | a;
    for (int shift = 24; shift >= 0; shift -= 8) z.push_back(std::byte((adler >> shift) & 0xff));
    return z;
}

// 3 x 2 x 2 samples: value(i,j,k) = i + 10 j + 100 k - 50, so the range is -50 .. 62.
std::vector<int16_t> gridI16() {
    std::vector<int16_t> v;
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 3; ++i) v.push_back(int16_t(i + 10 * j + 100 * k - 50));
    return v;
}

void checkGridI16(const Volume& v) {
    CHECK(v.dims == std::array<uint32_t, 3>{3, 2, 2});
    CHECK(v.type == VoxelType::I16);
    CHECK(v.value(0, 0, 0) == -50);
    CHECK(v.value(2, 1, 0) == -38);
    CHECK(v.value(1, 0, 1) == 51);
    CHECK(v.valueMin == -50);
    CHECK(v.valueMax == 62);
}

std::string header(const std::string& type, const std::string& more, const std::string& encoding = "raw") {
    return "NRRD0004\n# a comment\ntype: " + type + "\ndimension: 3\nsizes: 3 2 2\nencoding: " + encoding +
           "\nendian: little\nsome key:=some value\n" + more;
}

// A single-file NIfTI-1 image (header, 4 extension bytes, data) in either byte order.
struct Nifti {
    Bytes b = Bytes(352);
    bool big = false;
    template <class T>
    void put(std::size_t offset, T value) {
        std::memcpy(b.data() + offset, &value, sizeof value);
        if (big) swapBytes(b.data() + offset, 1, sizeof value);
    }
    Nifti(int16_t datatype, int16_t bitpix, bool bigEndian = false) : big(bigEndian) {
        put<int32_t>(0, 348);
        put<int16_t>(40, 3);
        for (int d = 0; d < 3; ++d) put<int16_t>(42 + 2 * std::size_t(d), int16_t(3 - (d > 0)));
        put<int16_t>(70, datatype);
        put<int16_t>(72, bitpix);
        for (int d = 1; d <= 3; ++d) put<float>(76 + 4 * std::size_t(d), 1.0f);
        put<float>(108, 352.0f);
        std::memcpy(b.data() + 344, "n+1\0", 4);
    }
    void sform(const std::array<float, 12>& rows) {
        put<int16_t>(254, 1);
        for (std::size_t i = 0; i < 12; ++i) put<float>(280 + 4 * i, rows[i]);
    }
};

// Loads `path` expecting an InputError whose message names `name` and says `problem`.
void checkRejects(const fs::path& path, const std::string& name, const std::string& problem,
                  const std::optional<RawLayout>& raw = std::nullopt) {
    CAPTURE(path);
    try {
        loadVolume(path, raw);
        FAIL("no InputError");
    } catch (const InputError& e) {
        const std::string msg = e.what();
        CAPTURE(msg);
        CHECK(msg.find(name) != std::string::npos);
        CHECK(msg.find(problem) != std::string::npos);
    }
}

} // namespace

TEST_CASE("io: voxel types") {
    CHECK(voxelBytes(VoxelType::U8) == 1);
    CHECK(voxelBytes(VoxelType::I16) == 2);
    CHECK(voxelBytes(VoxelType::U16) == 2);
    CHECK(voxelBytes(VoxelType::F32) == 4);
    for (auto t : {VoxelType::U8, VoxelType::I16, VoxelType::U16, VoxelType::F32})
        CHECK(parseVoxelType(voxelTypeName(t)) == t);
    CHECK(parseVoxelType("uchar") == VoxelType::U8);
    CHECK(parseVoxelType("int16") == VoxelType::I16);
    CHECK(parseVoxelType("ushort") == VoxelType::U16);
    CHECK(parseVoxelType("float32") == VoxelType::F32);
    CHECK_FALSE(parseVoxelType("double").has_value());
}

TEST_CASE("io: NRRD attached raw and gzip") {
    test::TempDir dir("io");
    const Bytes data = bytesOf(gridI16());
    writeFile(dir / "a.nrrd", bytesOf(header("short", "\n")) + data);
    checkGridI16(loadVolume(dir / "a.nrrd"));

    writeFile(dir / "b.nrrd", bytesOf(header("int16_t", "\n", "gzip")) + gzipCompress(data));
    const Volume v = loadVolume(dir / "b.nrrd");
    checkGridI16(v);
    CHECK(v.source == (dir / "b.nrrd").string());

    // Two concatenated gzip members, as `cat a.gz b.gz` makes.
    const Bytes half1(data.begin(), data.begin() + 10), half2(data.begin() + 10, data.end());
    writeFile(dir / "c.nrrd",
              bytesOf(header("short", "\n", "gz")) + gzipCompress(half1) + gzipCompress(half2));
    checkGridI16(loadVolume(dir / "c.nrrd"));
}

TEST_CASE("io: NRRD detached header with raw and raw.gz data") {
    test::TempDir dir("io");
    const Bytes data = bytesOf(gridI16());
    fs::create_directories(dir / "sub");
    writeFile(dir / "sub/x.raw", data);
    writeFile(dir / "sub/x.raw.gz", gzipCompress(data));
    writeText(dir / "sub/x.nhdr", header("short", "data file: x.raw\n"));
    writeText(dir / "sub/y.nhdr", header("short", "datafile: x.raw.gz\n", "gzip"));
    checkGridI16(loadVolume(dir / "sub/x.nhdr"));
    checkGridI16(loadVolume(dir / "sub/y.nhdr"));
}

TEST_CASE("io: NRRD byte order, skips and value types") {
    test::TempDir dir("io");
    SUBCASE("big-endian i16") {
        std::string h = header("short", "\n");
        h.replace(h.find("little"), 6, "big");
        writeFile(dir / "be.nrrd", bytesOf(h) + bytesOf(gridI16(), true));
        checkGridI16(loadVolume(dir / "be.nrrd"));
    }
    SUBCASE("byte skip and line skip in a detached file") {
        writeFile(dir / "d.raw", bytesOf("one\ntwo\nXYZ") + bytesOf(gridI16()));
        writeText(dir / "d.nhdr", header("short", "data file: d.raw\nline skip: 2\nbyte skip: 3\n"));
        checkGridI16(loadVolume(dir / "d.nhdr"));
        writeText(dir / "e.nhdr", header("short", "data file: d.raw\nbyte skip: -1\n"));
        checkGridI16(loadVolume(dir / "e.nhdr"));
    }
    SUBCASE("u8") {
        const std::vector<uint8_t> u8{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 255};
        writeFile(dir / "u8.nrrd", bytesOf(header("unsigned char", "\n")) + bytesOf(u8));
        const Volume v = loadVolume(dir / "u8.nrrd");
        CHECK(v.type == VoxelType::U8);
        CHECK(v.value(2, 1, 1) == 255);
        CHECK(v.valueMin == 0);
        CHECK(v.valueMax == 255);
    }
    SUBCASE("u16") {
        const std::vector<uint16_t> u16{7, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 65535};
        writeFile(dir / "u16.nrrd", bytesOf(header("ushort", "\n")) + bytesOf(u16));
        const Volume v = loadVolume(dir / "u16.nrrd");
        CHECK(v.type == VoxelType::U16);
        CHECK(v.value(0, 0, 0) == 7);
        CHECK(v.valueMin == 1);
        CHECK(v.valueMax == 65535);
    }
    SUBCASE("f32 range ignores NaN and infinities") {
        const float inf = std::numeric_limits<float>::infinity(),
                    nan = std::numeric_limits<float>::quiet_NaN();
        std::vector<float> f(12, nan);
        f[1] = 1.5f;
        f[2] = -2.25f;
        f[3] = inf;
        f[4] = -inf;
        writeFile(dir / "f.nrrd", bytesOf(header("float", "\n")) + bytesOf(f));
        Volume v = loadVolume(dir / "f.nrrd");
        CHECK(v.type == VoxelType::F32);
        CHECK(v.value(1, 0, 0) == 1.5);
        CHECK(v.valueMin == -2.25);
        CHECK(v.valueMax == 1.5);
        std::fill(f.begin(), f.end(), nan);
        writeFile(dir / "g.nrrd", bytesOf(header("float", "\n")) + bytesOf(f));
        v = loadVolume(dir / "g.nrrd");
        CHECK(v.valueMin == 0);
        CHECK(v.valueMax == 0);
    }
}

TEST_CASE("io: NRRD geometry") {
    test::TempDir dir("io");
    const Bytes data = bytesOf(gridI16());
    SUBCASE("spacings") {
        writeFile(dir / "s.nrrd", bytesOf(header("short", "spacings: 0.5 0.75 2\n\n")) + data);
        const Volume v = loadVolume(dir / "s.nrrd");
        CHECK(v.spacing == glm::dvec3(0.5, 0.75, 2));
        CHECK(v.directions == glm::dmat3(1.0));
    }
    SUBCASE("space directions and origin, LPS") {
        writeFile(
            dir / "lps.nrrd",
            bytesOf(header("short", "space: left-posterior-superior\nspace directions: (0,2,0) (-3,0,0) "
                                    "(0,0,4)\nspace origin: (10,20,30)\n\n")) +
                data);
        const Volume v = loadVolume(dir / "lps.nrrd");
        CHECK(v.spacing == glm::dvec3(2, 3, 4));
        CHECK(v.directions[0] == glm::dvec3(0, 1, 0));
        CHECK(v.directions[1] == glm::dvec3(-1, 0, 0));
        CHECK(v.origin == glm::dvec3(10, 20, 30));
        CHECK(v.worldOf(glm::dvec3(1, 1, 1)) == glm::dvec3(7, 22, 34));
    }
    SUBCASE("RAS is converted to LPS") {
        writeFile(dir / "ras.nrrd", bytesOf(header("short", "space: RAS\nspace directions: (1,0,0) (0,1,0) "
                                                            "(0,0,1.5)\nspace origin: (10,20,30)\n\n")) +
                                        data);
        const Volume v = loadVolume(dir / "ras.nrrd");
        CHECK(v.spacing == glm::dvec3(1, 1, 1.5));
        CHECK(v.directions[0] == glm::dvec3(-1, 0, 0));
        CHECK(v.directions[1] == glm::dvec3(0, -1, 0));
        CHECK(v.directions[2] == glm::dvec3(0, 0, 1));
        CHECK(v.origin == glm::dvec3(-10, -20, 30));
    }
}

TEST_CASE("io: MetaImage") {
    test::TempDir dir("io");
    const Bytes data = bytesOf(gridI16());
    const std::string common =
        "ObjectType = Image\nNDims = 3\nDimSize = 3 2 2\nElementType = MET_SHORT\n"
        "ElementSpacing = 0.5 1 2\nOffset = 1 2 3\nTransformMatrix = 0 1 0 -1 0 0 0 0 1\n";
    SUBCASE("mhd with a detached raw file") {
        writeFile(dir / "m.raw", data);
        writeText(dir / "m.mhd", common + "ElementByteOrderMSB = False\nElementDataFile = m.raw\n");
        const Volume v = loadVolume(dir / "m.mhd");
        checkGridI16(v);
        CHECK(v.spacing == glm::dvec3(0.5, 1, 2));
        CHECK(v.origin == glm::dvec3(1, 2, 3));
        CHECK(v.directions[0] == glm::dvec3(0, 1, 0));
        CHECK(v.directions[1] == glm::dvec3(-1, 0, 0));
        CHECK(v.worldOf(glm::dvec3(2, 1, 0)) == glm::dvec3(0, 3, 3));
    }
    SUBCASE("mha with LOCAL big-endian data") {
        writeFile(dir / "m.mha",
                  bytesOf(common + "BinaryDataByteOrderMSB = True\nElementDataFile = LOCAL\n") +
                      bytesOf(gridI16(), true));
        checkGridI16(loadVolume(dir / "m.mha"));
    }
    SUBCASE("compressed, zlib and gzip streams") {
        writeFile(dir / "z.mha",
                  bytesOf(common + "CompressedData = True\nElementDataFile = LOCAL\n") + zlibStored(data));
        checkGridI16(loadVolume(dir / "z.mha"));
        writeFile(dir / "g.raw", gzipCompress(data));
        writeText(dir / "g.mhd", common + "CompressedData = True\nElementDataFile = g.raw\n");
        checkGridI16(loadVolume(dir / "g.mhd"));
    }
    SUBCASE("HeaderSize and ElementSize") {
        writeFile(dir / "h.raw", bytesOf("01234567") + data);
        writeText(dir / "h.mhd", "NDims = 3\nDimSize = 3 2 2\nElementType = MET_SHORT\nElementSize = 1 1 3\n"
                                 "HeaderSize = 8\nElementDataFile = h.raw\n");
        const Volume v = loadVolume(dir / "h.mhd");
        checkGridI16(v);
        CHECK(v.spacing == glm::dvec3(1, 1, 3));
    }
}

TEST_CASE("io: NIfTI") {
    test::TempDir dir("io");
    SUBCASE(".nii with sform, RAS converted to LPS") {
        Nifti n(4, 16);
        n.sform({-2, 0, 0, 10, 0, -3, 0, 20, 0, 0, 4, 30});
        writeFile(dir / "s.nii", n.b + bytesOf(gridI16()));
        const Volume v = loadVolume(dir / "s.nii");
        checkGridI16(v);
        CHECK(v.spacing == glm::dvec3(2, 3, 4));
        CHECK(v.directions == glm::dmat3(1.0));
        CHECK(v.origin == glm::dvec3(-10, -20, 30));
    }
    SUBCASE(".nii with a permuting sform") {
        Nifti n(4, 16);
        n.sform({0, 2, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0});
        writeFile(dir / "p.nii", n.b + bytesOf(gridI16()));
        const Volume v = loadVolume(dir / "p.nii");
        CHECK(v.spacing == glm::dvec3(1, 2, 1));
        CHECK(v.directions[0] == glm::dvec3(0, -1, 0));
        CHECK(v.directions[1] == glm::dvec3(-1, 0, 0));
    }
    SUBCASE(".nii.gz with qform and value scaling") {
        Nifti n(2, 8);
        n.put<int16_t>(252, 1);
        n.put<float>(264, 1.0f); // quaternion d = 1: 180 degrees about z, i.e. RAS axes become LPS
        n.put<float>(80, 0.5f);
        n.put<float>(84, 0.5f);
        n.put<float>(88, 2.0f);
        n.put<float>(268, 5.0f);
        n.put<float>(272, 6.0f);
        n.put<float>(276, 7.0f);
        n.put<float>(112, 2.0f);  // scl_slope
        n.put<float>(116, -1.0f); // scl_inter
        const std::vector<uint8_t> u8{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
        writeFile(dir / "q.nii.gz", gzipCompress(n.b + bytesOf(u8)));
        const Volume v = loadVolume(dir / "q.nii.gz");
        CHECK(v.type == VoxelType::F32);
        CHECK(v.value(1, 0, 0) == 1);
        CHECK(v.value(2, 1, 1) == 21);
        CHECK(v.valueMin == -1);
        CHECK(v.valueMax == 21);
        CHECK(v.spacing == glm::dvec3(0.5, 0.5, 2));
        CHECK(glm::length(v.directions[0] - glm::dvec3(1, 0, 0)) < 1e-12);
        CHECK(glm::length(v.directions[1] - glm::dvec3(0, 1, 0)) < 1e-12);
        CHECK(v.origin == glm::dvec3(-5, -6, 7));
    }
    SUBCASE("big-endian u16 without sform or qform") {
        Nifti n(512, 16, true);
        n.put<float>(84, 2.0f);
        const std::vector<uint16_t> u16{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 60000};
        writeFile(dir / "be.nii", n.b + bytesOf(u16, true));
        const Volume v = loadVolume(dir / "be.nii");
        CHECK(v.type == VoxelType::U16);
        CHECK(v.value(2, 1, 1) == 60000);
        CHECK(v.valueMin == 1);
        CHECK(v.spacing == glm::dvec3(1, 2, 1));
        CHECK(v.directions[0] == glm::dvec3(-1, 0, 0));
    }
}

TEST_CASE("io: raw with a given layout") {
    test::TempDir dir("io");
    RawLayout layout;
    layout.dims = {3, 2, 2};
    layout.type = VoxelType::I16;
    layout.spacing = glm::dvec3(1, 1, 2.5);
    writeFile(dir / "r.raw", bytesOf(gridI16()));
    Volume v = loadVolume(dir / "r.raw", layout);
    checkGridI16(v);
    CHECK(v.spacing == glm::dvec3(1, 1, 2.5));

    layout.bigEndian = true;
    writeFile(dir / "r.img.gz", gzipCompress(bytesOf(gridI16(), true)));
    checkGridI16(loadVolume(dir / "r.img.gz", layout));

    layout = RawLayout{{2, 2, 1}, VoxelType::F32, glm::dvec3(1.0), false};
    writeFile(dir / "f.dat", bytesOf(std::vector<float>{0.25f, -1, 3, 2}));
    v = loadVolume(dir / "f.dat", layout);
    CHECK(v.value(0, 0, 0) == 0.25);
    CHECK(v.valueMin == -1);
    CHECK(v.valueMax == 3);
}

TEST_CASE("io: bundled headsq_quarter scan") {
    const Volume v = loadVolume(fs::path(ISOSCOPE_SOURCE_DIR) / "data/headsq_quarter.nhdr");
    CHECK(v.dims == std::array<uint32_t, 3>{64, 64, 93});
    CHECK(v.type == VoxelType::I16);
    CHECK(v.spacing == glm::dvec3(3.2, 3.2, 1.5));
    CHECK(v.valueMin == 0);
    CHECK(v.valueMax == 3926);
    CHECK(v.data.size() == v.byteSize());
}

TEST_CASE("io: malformed inputs throw InputError naming the file") {
    test::TempDir dir("io");
    const Bytes data = bytesOf(gridI16());
    SUBCASE("missing file") {
        checkRejects(dir / "nope.nrrd", "nope.nrrd", "not found");
    }
    SUBCASE("directory") {
        fs::create_directories(dir / "folder.nrrd");
        checkRejects(dir / "folder.nrrd", "folder.nrrd", "is a directory");
    }
    SUBCASE("empty file") {
        writeText(dir / "empty.nrrd", "");
        checkRejects(dir / "empty.nrrd", "empty.nrrd", "empty");
    }
    SUBCASE("unknown extension without raw layout") {
        writeFile(dir / "scan.foo", data);
        checkRejects(dir / "scan.foo", "scan.foo", "--raw-dims");
    }
    SUBCASE("bad magic") {
        writeFile(dir / "magic.nrrd", bytesOf("NRRX0004\n") + data);
        checkRejects(dir / "magic.nrrd", "magic.nrrd", "not a NRRD file");
        writeFile(dir / "magic.nii", Bytes(400, std::byte{7}));
        checkRejects(dir / "magic.nii", "magic.nii", "not a NIfTI-1 file");
        writeText(dir / "magic.mha", "\x89PNG\r\n\x1a\n");
        checkRejects(dir / "magic.mha", "magic.mha", "not a MetaImage header");
    }
    SUBCASE("missing required field") {
        writeFile(dir / "nosizes.nrrd",
                  bytesOf("NRRD0004\ntype: short\ndimension: 3\nencoding: raw\nendian: little\n\n") + data);
        checkRejects(dir / "nosizes.nrrd", "nosizes.nrrd", "missing required field 'sizes'");
        writeText(dir / "notype.mhd", "NDims = 3\nDimSize = 3 2 2\nElementDataFile = x.raw\n");
        checkRejects(dir / "notype.mhd", "notype.mhd", "'ElementType'");
    }
    SUBCASE("unsupported type") {
        writeFile(dir / "double.nrrd", bytesOf(header("double", "\n")) + data + data + data + data);
        checkRejects(dir / "double.nrrd", "double.nrrd", "unsupported type 'double'");
        writeText(dir / "double.mhd",
                  "NDims = 3\nDimSize = 3 2 2\nElementType = MET_DOUBLE\nElementDataFile = LOCAL\n");
        checkRejects(dir / "double.mhd", "double.mhd", "MET_DOUBLE");
        Nifti n(64, 64);
        writeFile(dir / "double.nii", n.b + data + data + data + data);
        checkRejects(dir / "double.nii", "double.nii", "float64");
    }
    SUBCASE("bad sizes") {
        std::string h = header("short", "\n");
        const auto withSizes = [&](const std::string& sizes) {
            std::string s = h;
            s.replace(s.find("3 2 2"), 5, sizes);
            return bytesOf(s);
        };
        writeFile(dir / "huge.nrrd", withSizes("100000 100000 100000") + data);
        checkRejects(dir / "huge.nrrd", "huge.nrrd", "too large");
        writeFile(dir / "wide.nrrd", withSizes("5000000000 1 1") + data);
        checkRejects(dir / "wide.nrrd", "wide.nrrd", "too large");
        writeFile(dir / "zero.nrrd", withSizes("3 0 2") + data);
        checkRejects(dir / "zero.nrrd", "zero.nrrd", "not positive");
        writeFile(dir / "neg.nrrd", withSizes("3 -2 2") + data);
        checkRejects(dir / "neg.nrrd", "neg.nrrd", "not positive");
        writeFile(dir / "text.nrrd", withSizes("3 two 2") + data);
        checkRejects(dir / "text.nrrd", "text.nrrd", "'two' is not a valid integer");
        writeFile(dir / "few.nrrd", withSizes("3 2") + data);
        checkRejects(dir / "few.nrrd", "few.nrrd", "needs 3 integers");
        std::string d4 = h;
        d4.replace(d4.find("dimension: 3"), 12, "dimension: 4");
        writeFile(dir / "dim4.nrrd", bytesOf(d4) + data);
        checkRejects(dir / "dim4.nrrd", "dim4.nrrd", "dimension 4 is not supported");
    }
    SUBCASE("bad spacing") {
        writeFile(dir / "sp0.nrrd", bytesOf(header("short", "spacings: 1 0 1\n\n")) + data);
        checkRejects(dir / "sp0.nrrd", "sp0.nrrd", "must be positive and finite");
        writeFile(dir / "spnan.nrrd", bytesOf(header("short", "spacings: 1 nan 1\n\n")) + data);
        checkRejects(dir / "spnan.nrrd", "spnan.nrrd", "must be positive and finite");
    }
    SUBCASE("missing detached data file") {
        writeText(dir / "lonely.nhdr", header("short", "data file: lonely.raw.gz\n", "gzip"));
        try {
            loadVolume(dir / "lonely.nhdr");
            FAIL("no InputError");
        } catch (const InputError& e) {
            const std::string msg = e.what();
            CHECK(msg.find(
                      "lonely.nhdr: data file 'lonely.raw.gz' not found next to the header (looked for ") !=
                  std::string::npos);
            CHECK(msg.find(fs::absolute(dir / "lonely.raw.gz").string()) != std::string::npos);
        }
        writeText(dir / "lonely.mhd",
                  "NDims = 3\nDimSize = 3 2 2\nElementType = MET_SHORT\nElementDataFile = gone.raw\n");
        checkRejects(dir / "lonely.mhd", "lonely.mhd", "data file 'gone.raw' not found");
    }
    SUBCASE("truncated and oversized data") {
        writeFile(dir / "short.nrrd", bytesOf(header("short", "\n")) + Bytes(data.begin(), data.end() - 3));
        checkRejects(dir / "short.nrrd", "short.nrrd", "truncated: data has 21 bytes, expected 24");
        writeFile(dir / "t.raw", Bytes(data.begin(), data.end() - 2));
        writeText(dir / "t.nhdr", header("short", "data file: t.raw\n"));
        checkRejects(dir / "t.nhdr", "t.raw", "truncated: data has 22 bytes, expected 24");
        writeFile(dir / "long.raw", data + data);
        writeText(dir / "long.nhdr", header("short", "data file: long.raw\n"));
        checkRejects(dir / "long.nhdr", "long.raw", "data has 48 bytes, expected 24");
        writeFile(dir / "trunc.nii", Nifti(4, 16).b + Bytes(data.begin(), data.end() - 1));
        checkRejects(dir / "trunc.nii", "trunc.nii", "truncated");
        RawLayout layout{{3, 2, 2}, VoxelType::I16, glm::dvec3(1.0), false};
        writeFile(dir / "odd.raw", Bytes(data.begin(), data.end() - 2));
        checkRejects(dir / "odd.raw", "odd.raw", "has 22 bytes, expected 24", layout);
        layout.dims = {3, 0, 2};
        checkRejects(dir / "odd.raw", "odd.raw", "not positive", layout);
    }
    SUBCASE("corrupt and truncated gzip") {
        writeFile(dir / "corrupt.nrrd",
                  bytesOf(header("short", "\n", "gzip")) +
                      Bytes{std::byte{0x1f}, std::byte{0x8b}, std::byte{8}, std::byte{0}} +
                      Bytes(40, std::byte{0xff}));
        checkRejects(dir / "corrupt.nrrd", "corrupt.nrrd", "corrupt compressed data");
        const Bytes gz = gzipCompress(data);
        writeFile(dir / "cut.raw.gz", Bytes(gz.begin(), gz.begin() + std::ptrdiff_t(gz.size() / 2)));
        writeText(dir / "cut.nhdr", header("short", "data file: cut.raw.gz\n", "gzip"));
        checkRejects(dir / "cut.nhdr", "cut.raw.gz", "truncated");
        writeFile(dir / "big.nrrd", bytesOf(header("short", "\n", "gzip")) + gzipCompress(data + data));
        checkRejects(dir / "big.nrrd", "big.nrrd", "more than the expected 24 bytes");
    }
    SUBCASE("NIfTI-2 and NIfTI pairs") {
        Bytes two(560);
        const int32_t size2 = 540;
        std::memcpy(two.data(), &size2, 4);
        writeFile(dir / "two.nii", two);
        checkRejects(dir / "two.nii", "two.nii", "NIfTI-2 is not supported");
        Nifti pair(4, 16);
        std::memcpy(pair.b.data() + 344, "ni1\0", 4);
        writeFile(dir / "pair.nii", pair.b + data);
        checkRejects(dir / "pair.nii", "pair.nii", ".hdr/.img pair");
    }
}

TEST_CASE("io: histogram") {
    test::TempDir dir("io");
    const std::vector<uint8_t> u8{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 9, 9};
    writeFile(dir / "h.nrrd", bytesOf(header("uchar", "\n")) + bytesOf(u8));
    const Histogram h = histogram(loadVolume(dir / "h.nrrd"), 10);
    CHECK(h.lo == 0);
    CHECK(h.hi == 9);
    CHECK(h.counts == std::vector<uint64_t>{1, 1, 1, 1, 1, 1, 1, 1, 1, 3});
    CHECK_THROWS_AS(histogram(Volume{}, 0), std::invalid_argument);
}

TEST_CASE("io: PNG round trip") {
    test::TempDir dir("io");
    std::vector<uint8_t> rgba;
    for (int i = 0; i < 3 * 2 * 4; ++i) rgba.push_back(uint8_t(i * 10));
    writePng(dir / "img.png", 3, 2, rgba);
    int w = 0, h = 0;
    CHECK(readPng(dir / "img.png", w, h) == rgba);
    CHECK(w == 3);
    CHECK(h == 2);
    CHECK(dir.entries() == 1);
    writeText(dir / "fake.png", "not a png");
    CHECK_THROWS_AS(readPng(dir / "fake.png", w, h), InputError);
    CHECK_THROWS_AS(writePng(dir / "bad.png", 3, 3, rgba), std::invalid_argument);
}

TEST_CASE("io: NRRD image writers round trip") {
    test::TempDir dir("io");
    const std::vector<float> f{0.5f, -1, 2, 3.25f, 1e-30f, 7};
    writeNrrd2D(dir / "f.nrrd", 3, 2, f);
    Nrrd2D r = readNrrd2D(dir / "f.nrrd");
    CHECK(r.w == 3);
    CHECK(r.h == 2);
    CHECK(r.type == "float");
    CHECK(r.values == std::vector<double>(f.begin(), f.end()));

    writeNrrd2D(dir / "u32.nrrd", 2, 1, std::vector<uint32_t>{7, 4000000000u});
    r = readNrrd2D(dir / "u32.nrrd");
    CHECK(r.type == "uint32");
    CHECK(r.values == std::vector<double>{7, 4000000000.0});

    writeNrrd2D(dir / "u64.nrrd", 1, 2, std::vector<uint64_t>{uint64_t(1) << 52, 3});
    r = readNrrd2D(dir / "u64.nrrd");
    CHECK(r.type == "uint64");
    CHECK(r.w == 1);
    CHECK(r.h == 2);
    CHECK(r.values == std::vector<double>{double(uint64_t(1) << 52), 3});

    std::vector<float> rgba(4 * 3 * 2);
    for (std::size_t i = 0; i < rgba.size(); ++i) rgba[i] = float(i) / 4;
    writeNrrdRgba(dir / "rgba.nrrd", 3, 2, rgba);
    const Volume v = loadVolume(dir / "rgba.nrrd");
    CHECK(v.dims == std::array<uint32_t, 3>{4, 3, 2});
    CHECK(v.value(1, 2, 1) == rgba[4 * (3 + 2) + 1]);
    CHECK_THROWS_WITH_AS(readNrrd2D(dir / "rgba.nrrd"), doctest::Contains("dimension 3"), InputError);
    CHECK(dir.entries() == 4);
}

TEST_CASE("io: writeFileAtomic never leaves partial output") {
    test::TempDir dir("io");
    const auto failing = [](std::ostream& out) {
        out << "partial";
        throw std::runtime_error("disk on fire");
    };
    CHECK_THROWS_WITH_AS(writeFileAtomic(dir / "new.txt", failing), doctest::Contains("disk on fire"),
                         std::runtime_error);
    CHECK_FALSE(fs::exists(dir / "new.txt"));
    CHECK(dir.entries() == 0);

    writeText(dir / "old.txt", "old");
    CHECK_THROWS_WITH_AS(writeFileAtomic(dir / "old.txt", failing),
                         doctest::Contains("old.txt: cannot write: "), std::runtime_error);
    CHECK(dir.entries() == 1);
    std::ifstream in(dir / "old.txt");
    CHECK(std::string(std::istreambuf_iterator<char>(in), {}) == "old");
    in.close();

    writeFileAtomic(dir / "old.txt", [](std::ostream& out) { out << "new"; });
    std::ifstream again(dir / "old.txt");
    CHECK(std::string(std::istreambuf_iterator<char>(again), {}) == "new");
    CHECK(dir.entries() == 1);

    CHECK_THROWS_AS(writeFileAtomic(dir / "missing/sub/x.txt", [](std::ostream&) {}), std::runtime_error);
    ensureParentDir(dir / "missing/sub/x.txt");
    CHECK(fs::is_directory(dir / "missing/sub"));
}
