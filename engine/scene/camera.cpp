#include "scene/camera.hpp"

#include "io/volume.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <string>

namespace iso {

namespace {

struct Basis {
    glm::dvec3 forward, right, up;
};

Basis basisOf(const Camera& cam) {
    Basis b;
    b.forward = glm::normalize(cam.target - cam.eye);
    b.right = glm::normalize(glm::cross(b.forward, cam.up));
    b.up = glm::cross(b.right, b.forward); // unit already: right and forward are orthonormal
    return b;
}

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& problem) {
    throw InputError(path.string() + ": " + problem);
}

glm::dvec3 readVec3(const nlohmann::json& j, const char* key, const std::filesystem::path& path) {
    if (!j.contains(key)) fail(path, std::string("missing \"") + key + "\"");
    const auto& a = j.at(key);
    if (!a.is_array() || a.size() != 3)
        fail(path, std::string("\"") + key + "\" must be an array of 3 numbers");
    glm::dvec3 v;
    for (int i = 0; i < 3; ++i) {
        if (!a[std::size_t(i)].is_number())
            fail(path, std::string("\"") + key + "\" must be an array of 3 numbers");
        v[i] = a[std::size_t(i)].get<double>();
        if (!std::isfinite(v[i])) fail(path, std::string("\"") + key + "\" must be finite");
    }
    return v;
}

double readNumber(const nlohmann::json& j, const char* key, const std::filesystem::path& path) {
    if (!j.contains(key)) fail(path, std::string("missing \"") + key + "\"");
    if (!j.at(key).is_number()) fail(path, std::string("\"") + key + "\" must be a number");
    return j.at(key).get<double>();
}

} // namespace

Ray primaryRay(const Camera& cam, int width, int height, int x, int y) {
    const Basis b = basisOf(cam);
    const double aspect = double(width) / double(height);
    // Pixel centre in normalised device coordinates, +x right and +y up.
    const double sx = (x + 0.5) / width * 2.0 - 1.0;
    const double sy = 1.0 - (y + 0.5) / height * 2.0;
    if (cam.orthographic) {
        const double halfH = cam.height / 2.0;
        return {cam.eye + sx * halfH * aspect * b.right + sy * halfH * b.up, b.forward};
    }
    const double tanHalf = std::tan(glm::radians(cam.fovyDeg) / 2.0);
    const glm::dvec3 dir = b.forward + sx * tanHalf * aspect * b.right + sy * tanHalf * b.up;
    return {cam.eye, glm::normalize(dir)};
}

Camera loadCamera(const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in) fail(path, "cannot open camera file");
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
        fail(path, std::string("invalid JSON: ") + e.what());
    }
    if (!j.is_object()) fail(path, "camera must be a JSON object");

    Camera cam;
    cam.eye = readVec3(j, "eye", path);
    cam.target = readVec3(j, "target", path);
    cam.up = readVec3(j, "up", path);

    std::string projection = "perspective";
    if (j.contains("projection")) {
        if (!j.at("projection").is_string()) fail(path, "\"projection\" must be a string");
        projection = j.at("projection").get<std::string>();
    }
    if (projection == "orthographic") {
        cam.orthographic = true;
        cam.height = readNumber(j, "height", path);
        if (!(cam.height > 0.0) || !std::isfinite(cam.height)) fail(path, "\"height\" must be > 0");
        // fovy is meaningless for an orthographic view; accept and check it if given anyway.
        if (j.contains("fovy_deg")) cam.fovyDeg = readNumber(j, "fovy_deg", path);
    } else if (projection == "perspective") {
        cam.fovyDeg = readNumber(j, "fovy_deg", path);
    } else {
        fail(path, "\"projection\" must be \"perspective\" or \"orthographic\", not \"" + projection + "\"");
    }
    if (!(cam.fovyDeg > 0.0 && cam.fovyDeg < 180.0)) fail(path, "\"fovy_deg\" must be in (0, 180)");

    const glm::dvec3 view = cam.target - cam.eye;
    if (glm::length(view) == 0.0) fail(path, "\"eye\" and \"target\" are the same point");
    if (glm::length(cam.up) == 0.0) fail(path, "\"up\" is the zero vector");
    // Relative test: a nearly parallel up would give a right vector dominated by rounding.
    const double s = glm::length(glm::cross(glm::normalize(view), glm::normalize(cam.up)));
    if (s < 1e-9) fail(path, "\"up\" is parallel to the view direction");
    return cam;
}

Camera frameVolume(const Volume& vol, int width, int height) {
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    std::array<glm::dvec3, 8> corners;
    for (int c = 0; c < 8; ++c) {
        glm::dvec3 ijk;
        for (int a = 0; a < 3; ++a) ijk[a] = (c >> a & 1) ? std::max(double(vol.dims[a]) - 1.0, 0.0) : 0.0;
        corners[std::size_t(c)] = vol.worldOf(ijk);
        lo = glm::min(lo, corners[std::size_t(c)]);
        hi = glm::max(hi, corners[std::size_t(c)]);
    }
    const glm::dvec3 centre = (lo + hi) / 2.0;
    double r = 0.0;
    for (const auto& p : corners) r = std::max(r, glm::length(p - centre));
    if (r == 0.0) r = 1.0; // a single sample: any positive distance shows it

    Camera cam;
    cam.fovyDeg = 30.0;
    cam.up = {0.0, 0.0, 1.0};
    const double halfV = glm::radians(cam.fovyDeg) / 2.0;
    const double halfH = std::atan(std::tan(halfV) * double(width) / double(height));
    const double dist = r / std::sin(std::min(halfV, halfH)) * 1.05;
    cam.target = centre;
    cam.eye = centre - dist * glm::dvec3(0.0, 1.0, 0.0); // LPS: anterior is -y
    return cam;
}

} // namespace iso
