// isoscope render: one frame of a scan's isosurface, written as PNG plus optional NRRD buffers.
#include "cli.hpp"

#include "io/image_write.hpp"
#include "render/renderer.hpp"
#include "vk/context.hpp"

#include <cstdio>
#include <cstring>

namespace iso::app {

namespace {

const char* kRenderHelp = R"(isoscope render SCAN --iso V [options]

Renders the isosurface {f = V} of the trilinear interpolant of SCAN's samples by exact ray
casting: every ray walks the cells it crosses and solves the cubic along it in each cell, so
the first hit is exact (no sampling step). V is in the scan's own units (stored values; for
CT in this repository's data, HU + 1024: skin 500, bone 1150-1350).

Options:
  --iso V               isovalue (required)
  --out FILE.png        image to write (default render.png)
  --size WxH            image size in pixels (default 512x512)
  --camera CAM.json     {"eye":[x,y,z],"target":[x,y,z],"up":[x,y,z],"fovy_deg":30}, or with
                        "projection":"orthographic","height":h; world units = the scan's
                        physical coordinates. Default: the whole volume from the front.
  --mode M              mono | ceir-shallow | ceir-deep | fvr (default ceir-shallow):
                        colour-enhanced modes colour each hit from the value's derivative along
                        the ray through the speed-colour map of a local transfer function; fvr is
                        full volume rendering with the same transfer function, for comparison
  --tf TF.json          local transfer function over [iso, iso + delta_v] (default: one for CT)
  --density-factor DF   delta_v / standard sample distance (default delta_v / smallest spacing)
  --shading phong|none  none outputs the material colour alone (default phong)
  --deep-reach D        ceir-deep: how far behind the hit to search, world units (default 16 voxels)
  --step S              fvr: sampling step in world units (default a quarter of the smallest spacing)
  --map-size M          intervals of the speed-colour map (default 256)
  --out-rgba FILE.nrrd  float32 4 x W x H linear RGBA before display encoding
  --crop i0,j0,k0,i1,j1,k1   render only this box (sample-index units, fractions allowed)
  --peel x0,y0,x1,y1    peeling window (repeatable): pixels in [x0,x1) x [y0,y1) show the next
                        layer of the surface; overlapping windows peel deeper
  --seeds SEEDS.json    {"foreground":[ids], "background":[ids]}: colour hits in those cells
  --out-depth FILE.nrrd float32 W x H: distance from the ray origin to the hit, -1 = no hit
  --out-ids FILE.nrrd   uint32 W x H: id i + nx*(j + ny*k) of the hit cell, 4294967295 = none
  --device NAME         Vulkan device (index or part of its name; see 'isoscope devices')
  --validate            turn on the Vulkan validation layers
%s
Example:
  isoscope render data/headsq_quarter.nhdr --iso 500 --size 256x256 --out skin.png
)";

} // namespace

int renderVerb(int argc, char** argv) {
    cli::Args args(argc, argv, 2, {"validate", "help", "raw-big-endian"});
    if (cli::printedHelp(args, kRenderHelp)) return 0;
    args.allowOnly(cli::sceneOptions({"out", "out-depth", "out-ids", "out-rgba"}));
    // Check every option before the (possibly slow) load, so mistakes are reported at once.
    RenderSettings settings = cli::sceneSettings(args, RenderMode::CeirShallow);
    const int width = settings.width, height = settings.height;
    std::string outPng = args.get("out").value_or("render.png");
    Volume vol = cli::loadScan(args);
    settings.camera = cli::cameraFor(args, vol, width, height);

    vk::Context ctx(cli::contextOptions(args));
    Renderer renderer(ctx);
    renderer.setVolume(vol);
    FrameOutputs wanted;
    wanted.depth = args.get("out-depth").has_value();
    wanted.voxelIds = args.get("out-ids").has_value();
    wanted.colour = true;
    Frame frame = renderer.render(settings, wanted);

    cli::Outputs outputs;
    writePng(outputs.stage(outPng), width, height, encodeSrgb8(frame.rgba));
    if (auto p = args.get("out-depth")) writeNrrd2D(outputs.stage(*p), width, height, frame.depth);
    if (auto p = args.get("out-ids")) writeNrrd2D(outputs.stage(*p), width, height, frame.voxelIds);
    if (auto p = args.get("out-rgba")) writeNrrdRgba(outputs.stage(*p), width, height, frame.rgba);
    outputs.commit();

    size_t hits = 0;
    for (size_t i = 0; i < frame.rgba.size(); i += 4) hits += frame.rgba[i + 3] > 0.0f;
    std::printf("wrote %s (%dx%d, %.1f%% of pixels on the surface)\n", outPng.c_str(), width, height,
                100.0 * double(hits) / (double(width) * height));
    std::printf("gpu: %s (%s)\n", ctx.deviceName().c_str(), ctx.deviceType());
    for (const auto& t : frame.timings)
        if (t.name.rfind("readback", 0) != 0)
            std::printf("gpu time: %s %.3f ms (%s)\n", t.name.c_str(), t.ms, modeName(settings.mode));
    if (ctx.validationMessages() > 0) {
        std::fprintf(stderr, "isoscope render: the Vulkan validation layers reported %llu problem(s)\n",
                     (unsigned long long)ctx.validationMessages());
        return 3;
    }
    return 0;
}

int devicesVerb(int argc, char** argv) {
    cli::Args args(argc, argv, 2, {"help"});
    if (args.flag("help")) {
        std::puts(
            "isoscope devices\n\nLists the Vulkan devices; pass an index or part of a name to --device.");
        return 0;
    }
    args.allowOnly({"help"});
    for (const auto& d : vk::Context::listDevices())
        std::printf("%u: %s (%s, Vulkan %u.%u)\n", d.index, d.name.c_str(), d.type,
                    VK_API_VERSION_MAJOR(d.apiVersion), VK_API_VERSION_MINOR(d.apiVersion));
    return 0;
}

} // namespace iso::app
