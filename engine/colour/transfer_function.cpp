#include "colour/transfer_function.hpp"

#include "io/io_util.hpp"
#include "io/volume.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace iso {

namespace {

using nlohmann::json;

constexpr int kMaxSamples = 4096;

// Index of the last point with x <= t (points non-empty, t within [first.x, last.x]).
std::size_t segmentOf(const std::vector<TfPoint>& points, double t) {
    auto it =
        std::upper_bound(points.begin(), points.end(), t, [](double v, const TfPoint& p) { return v < p.x; });
    return std::size_t(std::max<std::ptrdiff_t>(0, (it - points.begin()) - 1));
}

// Linear interpolation of a member between the points around x, with the end values held outside.
template <typename T, typename Get>
T interpolate(const std::vector<TfPoint>& points, double x, Get get) {
    if (x <= points.front().x) return get(points.front());
    if (x >= points.back().x) return get(points.back());
    const std::size_t i = segmentOf(points, x);
    const TfPoint& a = points[i];
    const TfPoint& b = points[std::min(i + 1, points.size() - 1)];
    if (b.x <= a.x) return get(a);
    const double f = (x - a.x) / (b.x - a.x);
    return get(a) + (get(b) - get(a)) * f;
}

bool inUnit(double v) {
    return std::isfinite(v) && v >= 0.0 && v <= 1.0;
}

std::string num(double v) {
    std::string s = std::to_string(v);
    // to_string gives 6 decimals; trailing zeros add nothing to a message.
    if (s.find('.') != std::string::npos) {
        while (!s.empty() && s.back() == '0') s.pop_back();
        if (!s.empty() && s.back() == '.') s.pop_back();
    }
    return s;
}

// The first problem with tf, or an empty string. Shared by the loader and validate() so a function read
// from a file and one built in code obey the same rules.
std::string problemWith(const LocalTransferFunction& tf) {
    if (!(std::isfinite(tf.deltaV) && tf.deltaV > 0.0)) return "delta_v must be a positive finite number";
    if (tf.samples < 1 || tf.samples > kMaxSamples)
        return "samples must be an integer in [1, " + std::to_string(kMaxSamples) + "]";
    if (tf.points.empty()) return "points must hold at least one point";
    for (std::size_t i = 0; i < tf.points.size(); ++i) {
        const TfPoint& p = tf.points[i];
        const std::string where = "points[" + std::to_string(i) + "]";
        if (!inUnit(p.x)) return where + ": x must be in [0, 1], got " + num(p.x);
        if (i > 0 && !(p.x > tf.points[i - 1].x))
            return where + ": x must be greater than the previous point's x (" + num(tf.points[i - 1].x) +
                   ")";
        for (int c = 0; c < 3; ++c)
            if (!inUnit(p.rgb[c])) return where + ": rgb must be three numbers in [0, 1]";
        if (!inUnit(p.alpha)) return where + ": alpha must be in [0, 1], got " + num(p.alpha);
    }
    return {};
}

[[noreturn]] void failTf(const std::filesystem::path& path, const std::string& problem) {
    throw InputError(path.string() + ": " + problem);
}

double numberAt(const std::filesystem::path& path, const json& j, const std::string& where) {
    if (!j.is_number()) failTf(path, where + " must be a number");
    return j.get<double>();
}

} // namespace

glm::dvec3 LocalTransferFunction::rgbAt(double x) const {
    if (points.empty()) return glm::dvec3(0.0);
    const double t = std::isnan(x) ? 0.0 : std::clamp(x, 0.0, 1.0);
    return interpolate<glm::dvec3>(points, t, [](const TfPoint& p) { return p.rgb; });
}

double LocalTransferFunction::alphaAt(double x) const {
    if (!(x >= 0.0)) return 0.0; // below the isovalue (and NaN): transparent
    if (x > 1.0) return 1.0;     // beyond isovalue + deltaV: opaque
    if (points.empty()) return 0.0;
    return interpolate<double>(points, x, [](const TfPoint& p) { return p.alpha; });
}

LocalTransferFunction loadTransferFunction(const std::filesystem::path& path) {
    const std::vector<std::byte> bytes = readFileBytes(path); // InputError "<path>: file not found" etc.
    json root;
    try {
        const auto* begin = reinterpret_cast<const char*>(bytes.data());
        root = json::parse(begin, begin + bytes.size());
    } catch (const json::exception& e) {
        failTf(path, std::string("bad JSON: ") + e.what());
    }
    if (!root.is_object()) failTf(path, "bad JSON: expected an object at the top level");

    LocalTransferFunction tf;
    if (root.contains("delta_v")) {
        const json& d = root.at("delta_v");
        if (!d.is_number()) failTf(path, "delta_v must be a positive finite number");
        tf.deltaV = d.get<double>();
    }
    if (root.contains("samples")) {
        const json& s = root.at("samples");
        // Integers only: 64.5 samples has no meaning, and a silent truncation would hide a typo.
        bool ok = s.is_number_integer();
        if (ok) {
            const auto v = s.is_number_unsigned() ? int64_t(std::min<uint64_t>(s.get<uint64_t>(), 1u << 30))
                                                  : s.get<int64_t>();
            ok = v >= 1 && v <= kMaxSamples;
            if (ok) tf.samples = int(v);
        }
        if (!ok) failTf(path, "samples must be an integer in [1, " + std::to_string(kMaxSamples) + "]");
    }
    if (!root.contains("points") || !root.at("points").is_array())
        failTf(path, "points must be an array of at least one point");
    const json& pts = root.at("points");
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const json& p = pts[i];
        const std::string where = "points[" + std::to_string(i) + "]";
        if (!p.is_object()) failTf(path, where + " must be an object with x, rgb and alpha");
        if (!p.contains("x") || !p.contains("rgb") || !p.contains("alpha"))
            failTf(path, where + " must have x, rgb and alpha");
        TfPoint tp;
        tp.x = numberAt(path, p.at("x"), where + ": x");
        const json& rgb = p.at("rgb");
        if (!rgb.is_array() || rgb.size() != 3) failTf(path, where + ": rgb must be three numbers in [0, 1]");
        for (int c = 0; c < 3; ++c) {
            if (!rgb[std::size_t(c)].is_number())
                failTf(path, where + ": rgb must be three numbers in [0, 1]");
            tp.rgb[c] = rgb[std::size_t(c)].get<double>();
        }
        tp.alpha = numberAt(path, p.at("alpha"), where + ": alpha");
        tf.points.push_back(tp);
    }
    if (const std::string problem = problemWith(tf); !problem.empty()) failTf(path, problem);
    return tf;
}

void validate(const LocalTransferFunction& tf) {
    if (const std::string problem = problemWith(tf); !problem.empty()) throw std::invalid_argument(problem);
}

LocalTransferFunction defaultTransferFunction() {
    // Why these values: the speed-colour map shows the near colours (small x) where the section is crossed
    // slowly (a low gradient: soft, thin or partial-volume structures), because opacity accumulates
    // before the ray gets deep, and the far colour (x = 1) where it is crossed fast (sharp boundaries).
    // So a warm pale colour with little opacity near x = 0 and a deeper red-brown, opaque at x = 1, makes
    // soft tissue read pale and skin-like while sharp boundaries (skin over air, cortical bone) read deep
    // and saturated, and the map spans a clear range of colours instead of one tone.
    // Opacity rises early (0.35 at x = 0.3) so that slow crossings at speeds around 0.1 - 1, typical of
    // CT with densityFactor's default, already stop in the pale part of the section.
    // deltaV = 100 suits Hounsfield units: most tissue boundaries change by hundreds of HU within a few
    // voxels, so the section is a few voxels deep at sharp edges and much deeper at soft ones.
    LocalTransferFunction tf;
    tf.deltaV = 100.0;
    tf.samples = 64;
    tf.points = {
        {0.0, {1.00, 0.90, 0.78}, 0.08},
        {0.3, {0.96, 0.70, 0.55}, 0.35},
        {0.7, {0.78, 0.35, 0.25}, 0.75},
        {1.0, {0.55, 0.13, 0.08}, 1.00},
    };
    return tf;
}

std::vector<glm::vec4> tabulate(const LocalTransferFunction& tf, int entries) {
    if (entries < 2) throw std::invalid_argument("tabulate: entries must be at least 2");
    std::vector<glm::vec4> out(static_cast<std::size_t>(entries));
    for (int k = 0; k < entries; ++k) {
        const double x = double(k) / double(entries - 1);
        out[std::size_t(k)] = glm::vec4(glm::vec3(tf.rgbAt(x)), float(tf.alphaAt(x)));
    }
    return out;
}

} // namespace iso
