#include "io/image_write.hpp"
#include "io/io_util.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <cstring>
#include <initializer_list>
#include <map>

namespace iso {

namespace fs = std::filesystem;

namespace {

struct NrrdType {
    std::string_view canonical;
    std::size_t bytes;
};

// The NRRD type names (with teem's synonyms) this project reads, mapped to one spelling each.
std::optional<NrrdType> nrrdType(std::string_view name) {
    struct Entry {
        NrrdType type;
        std::array<std::string_view, 6> names;
    };
    static constexpr Entry table[] = {
        {{"uint8", 1}, {"uchar", "unsigned char", "uint8", "uint8_t"}},
        {{"int16", 2}, {"short", "short int", "signed short", "signed short int", "int16", "int16_t"}},
        {{"uint16", 2}, {"ushort", "unsigned short", "unsigned short int", "uint16", "uint16_t"}},
        {{"float", 4}, {"float"}},
        {{"uint32", 4}, {"uint", "unsigned int", "uint32", "uint32_t"}},
        {{"uint64", 8}, {"ulonglong", "unsigned long long", "unsigned long long int", "uint64", "uint64_t"}},
    };
    if (name.empty()) return std::nullopt;
    for (const Entry& e : table)
        if (std::find(e.names.begin(), e.names.end(), name) != e.names.end()) return e.type;
    return std::nullopt;
}

struct NrrdData {
    NrrdType type;
    std::vector<int64_t> sizes;
    glm::dvec3 spacing{1.0}, origin{0.0};
    glm::dmat3 directions{1.0};
    std::vector<std::byte> payload; // native byte order
};

// Patient spaces NRRD may name, as the signs that take them to LPS.
std::optional<glm::dvec3> toLps(const std::string& space) {
    if (space == "left-posterior-superior" || space == "lps") return glm::dvec3(1, 1, 1);
    if (space == "right-anterior-superior" || space == "ras") return glm::dvec3(-1, -1, 1);
    if (space == "left-anterior-superior" || space == "las") return glm::dvec3(-1, 1, 1);
    return std::nullopt;
}

NrrdData readNrrd(const fs::path& path, int dimension, std::initializer_list<std::string_view> allowed) {
    std::vector<std::byte> bytes = readFileBytes(path);
    const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    if (!text.starts_with("NRRD000") || text.size() < 8 || text[7] < '1' || text[7] > '9')
        fail(path, "not a NRRD file (it must start with NRRD0001..NRRD0005)");

    std::map<std::string, std::string_view> fields;
    std::size_t pos = 0;
    std::optional<std::size_t> attachedAt;
    std::string_view line;
    nextLine(text, pos, line); // the magic
    for (int lineNo = 2; nextLine(text, pos, line); ++lineNo) {
        if (line.empty()) {
            attachedAt = pos;
            break;
        }
        const std::size_t colon = line.find(':');
        if (line.starts_with('#') ||
            (colon != std::string_view::npos && line.substr(colon).starts_with(":=")))
            continue; // comments and key/value pairs carry nothing we use
        auto field = splitField(line, ':');
        if (!field) fail(path, "header line " + std::to_string(lineNo) + " is not 'field: value'");
        fields[field->key] = field->value;
    }
    const auto get = [&](const char* key) -> std::optional<std::string_view> {
        const auto it = fields.find(key);
        return it == fields.end() ? std::nullopt : std::optional(it->second);
    };
    const auto require = [&](const char* key, const char* name) {
        const auto v = get(key);
        if (!v) fail(path, std::string("missing required field '") + name + "'");
        return *v;
    };

    NrrdData d;
    const std::string typeName = toLower(require("type", "type"));
    const auto type = nrrdType(typeName);
    std::string supported;
    for (std::string_view a : allowed) supported += (supported.empty() ? "" : ", ") + std::string(a);
    if (!type || std::find(allowed.begin(), allowed.end(), type->canonical) == allowed.end())
        fail(path, "unsupported type '" + typeName + "' (supported: " + supported + ")");
    d.type = *type;

    const int64_t dim = parseIntegers(path, "dimension", require("dimension", "dimension"), 1)[0];
    if (dim != dimension)
        fail(path, "dimension " + std::to_string(dim) + " is not supported (expected " +
                       std::to_string(dimension) + (dimension == 3 ? ": one scalar 3D volume)" : ")"));
    d.sizes = parseIntegers(path, "sizes", require("sizes", "sizes"), std::size_t(dim));
    const std::size_t expected = checkedSampleCount(path, d.sizes) * d.type.bytes;

    const std::string encoding = toLower(require("encoding", "encoding"));
    if (encoding != "raw" && encoding != "gzip" && encoding != "gz")
        fail(path, "unsupported encoding '" + encoding + "' (supported: raw, gzip)");
    bool bigEndian = false;
    if (d.type.bytes > 1) {
        const std::string endian = toLower(require("endian", "endian"));
        if (endian != "little" && endian != "big")
            fail(path, "field 'endian' must be 'little' or 'big', not '" + endian + "'");
        bigEndian = endian == "big";
    }

    if (dimension == 3) {
        if (const auto s = get("spacings"))
            d.spacing = glm::make_vec3(parseNumbers(path, "spacings", *s, 3).data());
        if (const auto s = get("spacedirections")) {
            if (toLower(*s).find("none") != std::string::npos)
                fail(path, "field 'space directions' has a non-spatial axis ('none'); expected a 3D volume");
            const auto n = parseNumbers(path, "space directions", *s, 9);
            d.spacing = splitAxes(path, glm::make_mat3(n.data()), d.directions);
        }
        if (const auto s = get("spaceorigin"))
            d.origin = glm::make_vec3(parseNumbers(path, "space origin", *s, 3).data());
        if (const auto s = get("space")) {
            const std::string space = toLower(*s);
            const auto signs = toLps(space);
            if (!signs)
                fail(path, "unsupported space '" + space +
                               "' (supported: left-posterior-superior, right-anterior-superior, "
                               "left-anterior-superior)");
            d.origin *= *signs;
            for (int a = 0; a < 3; ++a) d.directions[a] *= *signs;
        }
        checkSpacing(path, d.spacing);
    }

    // Everything from the header is read before `bytes` may be replaced: fields point into it.
    int64_t lineSkip = 0, byteSkip = 0;
    if (const auto s = get("lineskip")) lineSkip = parseIntegers(path, "line skip", *s, 1)[0];
    if (lineSkip < 0) fail(path, "field 'line skip' must not be negative");
    if (const auto s = get("byteskip")) byteSkip = parseIntegers(path, "byte skip", *s, 1)[0];
    fs::path dataPath = path;
    std::size_t offset = 0;
    if (const auto file = get("datafile")) {
        if (file->starts_with("LIST") || splitWords(*file).size() != 1)
            fail(path,
                 "data split over several files ('data file: " + std::string(*file) + "') is not supported");
        dataPath = findDataFile(path, *file);
        bytes = readFileBytes(dataPath);
    } else if (attachedAt) {
        offset = *attachedAt;
    } else {
        fail(path, "no data: the header has no 'data file' field and no blank line before attached data");
    }
    for (int64_t i = 0; i < lineSkip; ++i) {
        const auto nl = std::find(bytes.begin() + std::ptrdiff_t(offset), bytes.end(), std::byte{'\n'});
        if (nl == bytes.end())
            fail(dataPath, "line skip " + std::to_string(lineSkip) + " runs past the end of the data");
        offset = std::size_t(nl - bytes.begin()) + 1;
    }
    d.payload = extractPayload(dataPath, std::move(bytes), offset, byteSkip, encoding != "raw", expected);
    if (bigEndian) swapBytes(d.payload.data(), d.payload.size() / d.type.bytes, d.type.bytes);
    return d;
}

} // namespace

Volume loadNrrd(const fs::path& path) {
    NrrdData d = readNrrd(path, 3, {"uint8", "int16", "uint16", "float"});
    Volume v;
    for (int a = 0; a < 3; ++a) v.dims[a] = uint32_t(d.sizes[a]);
    v.type = *parseVoxelType(std::string(d.type.canonical));
    v.spacing = d.spacing;
    v.origin = d.origin;
    v.directions = d.directions;
    finishVolume(v, path, std::move(d.payload), false);
    return v;
}

Nrrd2D readNrrd2D(const fs::path& path) {
    NrrdData d = readNrrd(path, 2, {"float", "uint32", "uint64"});
    Nrrd2D r{int(d.sizes[0]), int(d.sizes[1]), std::string(d.type.canonical), {}};
    r.values.resize(d.payload.size() / d.type.bytes);
    for (std::size_t i = 0; i < r.values.size(); ++i) {
        const std::byte* p = d.payload.data() + i * d.type.bytes;
        if (r.type == "float") {
            float f;
            std::memcpy(&f, p, 4);
            r.values[i] = f;
        } else if (r.type == "uint32") {
            uint32_t u;
            std::memcpy(&u, p, 4);
            r.values[i] = u;
        } else {
            uint64_t u;
            std::memcpy(&u, p, 8);
            r.values[i] = double(u);
        }
    }
    return r;
}

} // namespace iso
