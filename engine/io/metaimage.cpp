#include "io/io_util.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <map>

namespace iso {

namespace fs = std::filesystem;

Volume loadMetaImage(const fs::path& path) {
    std::vector<std::byte> bytes = readFileBytes(path);
    const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());

    // The header ends with the ElementDataFile line; for LOCAL the data follows it directly.
    std::map<std::string, std::string_view> fields;
    std::size_t pos = 0, dataAt = 0;
    std::string_view line;
    for (int lineNo = 1; nextLine(text, pos, line); ++lineNo) {
        if (trim(line).empty()) continue;
        const auto field = splitField(line, '=');
        if (!field)
            fail(path, lineNo == 1 ? "not a MetaImage header (expected 'Key = Value' lines)"
                                   : "header line " + std::to_string(lineNo) + " is not 'Key = Value'");
        fields[field->key] = field->value;
        if (field->key == "elementdatafile") {
            dataAt = pos;
            break;
        }
    }
    const auto get = [&](std::initializer_list<const char*> keys) -> std::optional<std::string_view> {
        for (const char* key : keys)
            if (const auto it = fields.find(key); it != fields.end()) return it->second;
        return std::nullopt;
    };
    const auto require = [&](const char* key, const char* name) {
        const auto v = get({key});
        if (!v) fail(path, std::string("missing required field '") + name + "'");
        return *v;
    };
    const auto flag = [&](std::initializer_list<const char*> keys, const char* name) {
        const auto v = get(keys);
        if (!v) return false;
        const std::string s = toLower(*v);
        if (s != "true" && s != "false" && s != "1" && s != "0")
            fail(path,
                 std::string("field '") + name + "' must be True or False, not '" + std::string(*v) + "'");
        return s == "true" || s == "1";
    };

    const std::string dataFile(require("elementdatafile", "ElementDataFile"));
    if (const auto t = get({"objecttype"}); t && toLower(*t) != "image")
        fail(path, "ObjectType '" + std::string(*t) + "' is not an image");
    const int64_t ndims = parseIntegers(path, "NDims", require("ndims", "NDims"), 1)[0];
    if (ndims != 3) fail(path, "NDims " + std::to_string(ndims) + " is not supported (expected 3)");
    if (const auto c = get({"elementnumberofchannels"});
        c && parseIntegers(path, "ElementNumberOfChannels", *c, 1)[0] != 1)
        fail(path,
             "multi-channel images are not supported (ElementNumberOfChannels " + std::string(*c) + ")");
    if (get({"binarydata"}) && !flag({"binarydata"}, "BinaryData"))
        fail(path, "ASCII data (BinaryData = False) is not supported");

    Volume v;
    const auto sizes = parseIntegers(path, "DimSize", require("dimsize", "DimSize"), 3);
    const std::size_t expected = checkedSampleCount(path, sizes);
    for (int a = 0; a < 3; ++a) v.dims[a] = uint32_t(sizes[a]);

    const std::string elementType(require("elementtype", "ElementType"));
    static const std::map<std::string, VoxelType, std::less<>> types = {{"MET_UCHAR", VoxelType::U8},
                                                                        {"MET_SHORT", VoxelType::I16},
                                                                        {"MET_USHORT", VoxelType::U16},
                                                                        {"MET_FLOAT", VoxelType::F32}};
    const auto type = types.find(elementType);
    if (type == types.end())
        fail(path, "unsupported ElementType '" + elementType +
                       "' (supported: MET_UCHAR, MET_SHORT, MET_USHORT, MET_FLOAT)");
    v.type = type->second;

    if (const auto s = get({"elementspacing", "elementsize"}))
        v.spacing = glm::make_vec3(parseNumbers(path, "ElementSpacing", *s, 3).data());
    checkSpacing(path, v.spacing);
    if (const auto s = get({"offset", "origin", "position"}))
        v.origin = glm::make_vec3(parseNumbers(path, "Offset", *s, 3).data());
    // ITK writes the direction of axis i as numbers 3i..3i+2, i.e. the matrix's columns in turn,
    // which is glm's column-major order. Lengths are dropped: spacing comes from ElementSpacing.
    if (const auto s = get({"transformmatrix", "rotation", "orientation"}))
        splitAxes(path, glm::make_mat3(parseNumbers(path, "TransformMatrix", *s, 9).data()), v.directions);

    const bool bigEndian = flag({"elementbyteordermsb", "binarydatabyteordermsb"}, "ElementByteOrderMSB");
    const bool compressed = flag({"compresseddata"}, "CompressedData");
    const auto headerSize = get({"headersize"});
    const int64_t skip = headerSize ? parseIntegers(path, "HeaderSize", *headerSize, 1)[0] : 0;

    fs::path dataPath = path;
    if (toLower(dataFile) == "local") {
        if (dataAt >= bytes.size()) fail(path, "no data after 'ElementDataFile = LOCAL'");
    } else {
        if (toLower(dataFile).starts_with("list") || splitWords(dataFile).size() != 1 ||
            dataFile.find('%') != std::string::npos)
            fail(path,
                 "data split over several files ('ElementDataFile = " + dataFile + "') is not supported");
        dataPath = findDataFile(path, dataFile);
        bytes = readFileBytes(dataPath);
        dataAt = 0;
    }
    finishVolume(
        v, path,
        extractPayload(dataPath, std::move(bytes), dataAt, skip, compressed, expected * voxelBytes(v.type)),
        bigEndian);
    return v;
}

} // namespace iso
