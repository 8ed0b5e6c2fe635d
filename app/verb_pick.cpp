// isoscope pick: which voxel cell a pixel's ray hits (paper §5.3), from the same rays and the same
// voxel-id buffer as the rendered image, so crop and peel apply exactly as they do to images.
#include "cli.hpp"

#include "render/renderer.hpp"
#include "vk/context.hpp"

#include <algorithm>
#include <cstdio>
#include <glm/gtc/matrix_inverse.hpp>

namespace iso::app {

namespace {

const char* kPickHelp = R"(isoscope pick SCAN --iso V (--at x,y | --rect x0,y0,x1,y1) [options]

Prints, as one JSON line, what the ray through pixel (x, y) hits:
  {"hit":true, "id":..., "ijk":[i,j,k], "world":[x,y,z], "t":..., "value":...}  or  {"hit":false}
where id = i + nx*(j + ny*k) names the cell whose lowest corner is sample (i,j,k), world is the
hit point, t its distance along the ray and value the interpolated scan value there.
With --rect, prints {"ids":[...]}: the sorted unique cell ids hit by the pixels in
[x0,x1) x [y0,y1), e.g. to collect seeds for segmentation.

Options: --size, --camera, --crop, --peel and the scan options work as for 'isoscope render';
the pick sees exactly what that image shows.
%s
Example:
  isoscope pick data/headsq_quarter.nhdr --iso 500 --size 256x256 --at 128,128
)";

double trilinear(const Volume& v, glm::dvec3 p) {
    glm::dvec3 hi(v.dims[0] - 1.0, v.dims[1] - 1.0, v.dims[2] - 1.0);
    p = glm::clamp(p, glm::dvec3(0.0), hi);
    glm::uvec3 c =
        glm::min(glm::uvec3(glm::floor(p)), glm::uvec3(v.dims[0] - 2, v.dims[1] - 2, v.dims[2] - 2));
    glm::dvec3 w = p - glm::dvec3(c);
    double out = 0.0;
    for (uint32_t k = 0; k < 2; ++k)
        for (uint32_t j = 0; j < 2; ++j)
            for (uint32_t i = 0; i < 2; ++i)
                out += v.value(c.x + i, c.y + j, c.z + k) * (i ? w.x : 1 - w.x) * (j ? w.y : 1 - w.y) *
                       (k ? w.z : 1 - w.z);
    return out;
}

} // namespace

int pickVerb(int argc, char** argv) {
    cli::Args args(argc, argv, 2, {"validate", "help", "raw-big-endian"});
    if (cli::printedHelp(args, kPickHelp)) return 0;
    args.allowOnly(cli::sceneOptions({"at", "rect"}));
    RenderSettings settings = cli::sceneSettings(args, RenderMode::Mono);
    if (settings.mode == RenderMode::Fvr) throw cli::UsageError("--mode fvr shows no surface to pick");
    const int w = settings.width, h = settings.height;
    std::vector<double> at, rect;
    if (auto a = args.get("at")) at = cli::parseList("at", *a, 2);
    if (auto r = args.get("rect")) rect = cli::parseList("rect", *r, 4);
    if (at.empty() == rect.empty())
        throw cli::UsageError("give exactly one of --at x,y or --rect x0,y0,x1,y1");
    if (!at.empty() && (at[0] < 0 || at[1] < 0 || at[0] >= w || at[1] >= h || at[0] != std::floor(at[0]) ||
                        at[1] != std::floor(at[1])))
        throw cli::UsageError("--at: a whole pixel inside the " + std::to_string(w) + "x" +
                              std::to_string(h) + " image");
    if (!rect.empty() && (rect[0] >= rect[2] || rect[1] >= rect[3]))
        throw cli::UsageError("--rect: need x0 < x1 and y0 < y1");

    Volume vol = cli::loadScan(args);
    settings.camera = cli::cameraFor(args, vol, w, h);
    vk::Context ctx(cli::contextOptions(args));
    Renderer renderer(ctx);
    renderer.setVolume(vol);
    Frame frame = renderer.render(settings, {false, true, true});

    if (!rect.empty()) {
        std::vector<uint32_t> ids;
        for (int y = std::max(0, int(rect[1])); y < std::min(h, int(std::ceil(rect[3]))); ++y)
            for (int x = std::max(0, int(rect[0])); x < std::min(w, int(std::ceil(rect[2]))); ++x) {
                uint32_t id = frame.voxelIds[size_t(y) * size_t(w) + size_t(x)];
                if (id != 0xFFFFFFFFu) ids.push_back(id);
            }
        std::sort(ids.begin(), ids.end());
        ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
        std::string out = "{\"ids\":[";
        for (size_t i = 0; i < ids.size(); ++i) {
            if (i) out += ',';
            out += std::to_string(ids[i]);
        }
        std::printf("%s]}\n", out.c_str());
        return ctx.validationMessages() ? 3 : 0;
    }
    const int x = int(at[0]), y = int(at[1]);
    const size_t pixel = size_t(y) * size_t(w) + size_t(x);
    const uint32_t id = frame.voxelIds[pixel];
    if (id == 0xFFFFFFFFu) {
        std::printf("{\"hit\":false}\n");
        return ctx.validationMessages() ? 3 : 0;
    }
    const double t = frame.depth[pixel];
    Ray ray = primaryRay(settings.camera, w, h, x, y);
    glm::dvec3 world = ray.origin + t * ray.dir;
    glm::dmat3 M =
        vol.directions * glm::dmat3(glm::dvec3(vol.spacing.x, 0, 0), glm::dvec3(0, vol.spacing.y, 0),
                                    glm::dvec3(0, 0, vol.spacing.z));
    glm::dvec3 index = glm::inverse(M) * (world - vol.origin);
    const uint32_t nx = vol.dims[0], ny = vol.dims[1];
    std::printf("{\"hit\":true, \"id\":%u, \"ijk\":[%u,%u,%u], \"world\":[%.9g,%.9g,%.9g], \"t\":%.9g, "
                "\"value\":%.9g}\n",
                id, id % nx, (id / nx) % ny, id / (nx * ny), world.x, world.y, world.z, t,
                trilinear(vol, index));
    return ctx.validationMessages() ? 3 : 0;
}

} // namespace iso::app
