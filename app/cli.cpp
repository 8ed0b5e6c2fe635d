#include "cli.hpp"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <tuple>
#include <charconv>
#include <cstdio>
#include <cmath>
#include <random>
#include <sstream>
#include <system_error>
#include <unistd.h>

namespace iso::cli {

const char* kScanOptionsHelp =
    "Scans: NRRD (.nrrd, .nhdr + data file; raw or gzip), MetaImage (.mhd, .mha; raw or compressed),\n"
    "NIfTI-1 (.nii, .nii.gz), or a headerless raw file described by:\n"
    "  --raw-dims X,Y,Z         samples per axis\n"
    "  --raw-type T             u8, i16, u16 or f32\n"
    "  --raw-spacing SX,SY,SZ   sample spacing (default 1,1,1)\n"
    "  --raw-big-endian         the raw file is big-endian\n";

Args::Args(int argc, char** argv, int first, std::vector<std::string> flags) : flags_(std::move(flags)) {
    for (int i = first; i < argc; ++i) {
        std::string a = argv[i];
        if (a.rfind("--", 0) != 0 || a == "--") {
            positional_.push_back(a);
            continue;
        }
        std::string name = a.substr(2), value;
        auto eq = name.find('=');
        if (eq != std::string::npos) {
            value = name.substr(eq + 1);
            name = name.substr(0, eq);
        } else if (std::find(flags_.begin(), flags_.end(), name) != flags_.end()) {
            value = "1";
        } else {
            if (i + 1 >= argc) throw UsageError("--" + name + " needs a value");
            value = argv[++i];
        }
        values_.emplace(name, value);
    }
}

bool Args::flag(const std::string& name) const {
    return values_.count(name) > 0;
}

std::optional<std::string> Args::get(const std::string& name) const {
    auto range = values_.equal_range(name);
    if (range.first == range.second) return std::nullopt;
    return std::prev(range.second)->second; // the last one given wins
}

std::vector<std::string> Args::all(const std::string& name) const {
    std::vector<std::string> out;
    auto range = values_.equal_range(name);
    for (auto it = range.first; it != range.second; ++it) out.push_back(it->second);
    return out;
}

std::string Args::require(const std::string& name, const std::string& hint) const {
    auto v = get(name);
    if (!v) throw UsageError("missing --" + name + " (" + hint + ")");
    return *v;
}

void Args::allowOnly(const std::vector<std::string>& known) const {
    for (const auto& [name, value] : values_)
        if (std::find(known.begin(), known.end(), name) == known.end())
            throw UsageError("unknown option --" + name + " (see --help)");
}

double parseNumber(const std::string& option, const std::string& text) {
    double v = 0.0;
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v))
        throw UsageError("--" + option + ": '" + text + "' is not a finite number");
    return v;
}

std::pair<int, int> parseSize(const std::string& option, const std::string& text) {
    auto x = text.find('x');
    int w = 0, h = 0;
    bool ok = x != std::string::npos;
    if (ok) {
        auto r1 = std::from_chars(text.data(), text.data() + x, w);
        auto r2 = std::from_chars(text.data() + x + 1, text.data() + text.size(), h);
        ok = r1.ec == std::errc() && r1.ptr == text.data() + x && r2.ec == std::errc() &&
             r2.ptr == text.data() + text.size();
    }
    if (!ok || w <= 0 || h <= 0 || w > 16384 || h > 16384)
        throw UsageError("--" + option + ": '" + text + "' is not a size like 512x512 (1 to 16384 per side)");
    return {w, h};
}

std::vector<double> parseList(const std::string& option, const std::string& text, size_t count) {
    std::vector<double> out;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) out.push_back(parseNumber(option, item));
    if (out.size() != count)
        throw UsageError("--" + option + ": expected " + std::to_string(count) +
                         " comma-separated numbers, got '" + text + "'");
    return out;
}

Volume loadScan(const Args& args) {
    if (args.positional().empty()) throw UsageError("no scan given (the first argument is the scan file)");
    if (args.positional().size() > 1) throw UsageError("unexpected argument '" + args.positional()[1] + "'");
    std::optional<RawLayout> raw;
    if (args.get("raw-dims") || args.get("raw-type")) {
        RawLayout layout;
        auto dims = parseList("raw-dims", args.require("raw-dims", "samples per axis, e.g. 256,256,128"), 3);
        for (int a = 0; a < 3; ++a) {
            if (dims[a] < 1 || dims[a] != std::floor(dims[a]) || dims[a] > 1e6)
                throw UsageError("--raw-dims: each size must be a whole number from 1 to 1000000");
            layout.dims[a] = uint32_t(dims[a]);
        }
        std::string type = args.require("raw-type", "u8, i16, u16 or f32");
        auto t = parseVoxelType(type);
        if (!t) throw UsageError("--raw-type: unknown type '" + type + "' (use u8, i16, u16 or f32)");
        layout.type = *t;
        if (auto sp = args.get("raw-spacing")) {
            auto v = parseList("raw-spacing", *sp, 3);
            for (double x : v)
                if (x <= 0) throw UsageError("--raw-spacing: spacings must be positive");
            layout.spacing = {v[0], v[1], v[2]};
        }
        layout.bigEndian = args.flag("raw-big-endian");
        raw = layout;
    }
    return loadVolume(args.positional()[0], raw);
}

RenderSettings sceneSettings(const Args& args, RenderMode defaultMode) {
    RenderSettings s;
    s.iso = parseNumber("iso", args.require("iso", "the isovalue in the scan's units, e.g. --iso 500"));
    std::tie(s.width, s.height) = parseSize("size", args.get("size").value_or("512x512"));
    if (auto m = args.get("mode")) {
        auto mode = parseMode(*m);
        if (!mode) throw UsageError("--mode: '" + *m + "' is not one of mono, ceir-shallow, ceir-deep, fvr");
        s.mode = *mode;
    } else {
        s.mode = defaultMode;
    }
    if (auto tf = args.get("tf")) s.tf = loadTransferFunction(*tf);
    auto positive = [&](const char* name) -> std::optional<double> {
        auto v = args.get(name);
        if (!v) return std::nullopt;
        double x = parseNumber(name, *v);
        if (x <= 0) throw UsageError(std::string("--") + name + ": must be positive");
        return x;
    };
    s.densityFactor = positive("density-factor");
    s.deepReach = positive("deep-reach");
    s.fvrStep = positive("step");
    if (auto m = positive("map-size")) {
        if (*m != std::floor(*m) || *m > 65536)
            throw UsageError("--map-size: a whole number from 1 to 65536");
        s.mapIntervals = int(*m);
    }
    std::string shading = args.get("shading").value_or("phong");
    if (shading != "phong" && shading != "none") throw UsageError("--shading: 'phong' or 'none'");
    s.shade = shading == "phong";
    if (auto c = args.get("crop")) {
        auto v = parseList("crop", *c, 6);
        s.crop = std::array<double, 6>{v[0], v[1], v[2], v[3], v[4], v[5]};
        for (int a = 0; a < 3; ++a)
            if (v[a] > v[a + 3]) throw UsageError("--crop: each lower bound must not exceed its upper bound");
    }
    for (const auto& w : args.all("peel")) {
        auto v = parseList("peel", w, 4);
        for (double x : v)
            if (x != std::floor(x))
                throw UsageError("--peel: pixel coordinates are whole numbers: '" + w + "'");
        if (v[0] >= v[2] || v[1] >= v[3]) throw UsageError("--peel: need x0 < x1 and y0 < y1: '" + w + "'");
        addPeelWindow(s.peelBuffer, s.width, s.height, int(v[0]), int(v[1]), int(v[2]), int(v[3]));
    }
    if (auto path = args.get("seeds")) {
        std::ifstream in(*path);
        if (!in) throw InputError(*path + ": cannot open the seed file");
        nlohmann::json j;
        try {
            j = nlohmann::json::parse(in);
            for (const char* key : {"foreground", "background"}) {
                auto& list = key[0] == 'f' ? s.foregroundSeeds : s.backgroundSeeds;
                if (!j.contains(key)) continue;
                for (const auto& id : j.at(key)) {
                    if (!id.is_number_unsigned() || id.get<uint64_t>() > 0xFFFFFFFEull)
                        throw InputError(*path + ": \"" + key + "\" must list voxel ids (whole numbers)");
                    list.push_back(id.get<uint32_t>());
                }
            }
        } catch (const nlohmann::json::exception& e) {
            throw InputError(*path +
                             ": not a seed file ({\"foreground\":[ids],\"background\":[ids]}): " + e.what());
        }
    }
    return s;
}

vk::ContextOptions contextOptions(const Args& args) {
    vk::ContextOptions options;
    options.validation = args.flag("validate");
    options.device = args.get("device").value_or("");
    return options;
}

bool printedHelp(const Args& args, const char* help) {
    if (!args.flag("help")) return false;
    std::printf(help, kScanOptionsHelp);
    return true;
}

std::vector<std::string> sceneOptions(std::vector<std::string> extra) {
    std::vector<std::string> known{
        "iso",      "size",       "camera",      "crop",           "device", "validate", "help",
        "raw-dims", "raw-type",   "raw-spacing", "raw-big-endian", "mode",   "tf",       "density-factor",
        "shading",  "deep-reach", "step",        "map-size",       "peel",   "seeds"};
    known.insert(known.end(), extra.begin(), extra.end());
    return known;
}

Camera cameraFor(const Args& args, const Volume& vol, int width, int height) {
    if (auto path = args.get("camera")) return loadCamera(*path);
    return frameVolume(vol, width, height);
}

Outputs::~Outputs() {
    for (const auto& [tmp, dst] : staged_) {
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
    }
}

std::filesystem::path Outputs::stage(const std::filesystem::path& finalPath) {
    if (finalPath.empty()) throw UsageError("an output path is empty");
    auto dir = finalPath.parent_path();
    if (!dir.empty() && !std::filesystem::is_directory(dir)) {
        std::error_code ec;
        std::filesystem::create_directories(dir, ec);
        if (ec)
            throw std::runtime_error(finalPath.string() + ": cannot create folder " + dir.string() + ": " +
                                     ec.message());
    }
    if (std::filesystem::is_directory(finalPath))
        throw UsageError(finalPath.string() + ": is a folder; give a file name");
    std::filesystem::path tmp = finalPath;
    tmp += ".isoscope-tmp-" + std::to_string(::getpid()) + "-" + std::to_string(staged_.size());
    staged_.push_back({tmp, finalPath});
    return tmp;
}

void Outputs::commit() {
    for (const auto& [tmp, dst] : staged_) {
        std::error_code ec;
        std::filesystem::rename(tmp, dst, ec);
        if (ec) throw std::runtime_error(dst.string() + ": cannot write: " + ec.message());
    }
    staged_.clear();
}

} // namespace iso::cli
