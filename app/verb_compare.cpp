// isoscope compare: CEIR against the full volume rendering it approximates (paper §6), same view,
// same transfer function: both GPU times, the image difference, and a side-by-side picture.
#include "cli.hpp"

#include "io/image_write.hpp"
#include "render/renderer.hpp"
#include "vk/context.hpp"

#include <cmath>
#include <cstdio>

namespace iso::app {

namespace {

const char* kCompareHelp = R"(isoscope compare SCAN --iso V [options]

Renders the same view twice: with colour-enhanced isosurface rendering (--mode, default
ceir-shallow) and with full volume rendering (fvr) of the same local transfer function. Prints
both GPU times and the colour difference (RMSE and max, linear RGB in 0..255 units, over the
pixels where both show the surface: CEIR hits and FVR's accumulated opacity is at least 0.5),
and writes the two images side by side (CEIR left, FVR right).

Options: as for 'isoscope render' (--size, --camera, --tf, --density-factor, --shading,
--deep-reach, --step, --map-size, --crop, ...), plus
  --out FILE.png   side-by-side image (default compare.png)
%s
Example:
  isoscope compare data/headsq_quarter.nhdr --iso 500 --size 256x256 --out compare.png
)";

} // namespace

int compareVerb(int argc, char** argv) {
    cli::Args args(argc, argv, 2, {"validate", "help", "raw-big-endian"});
    if (cli::printedHelp(args, kCompareHelp)) return 0;
    args.allowOnly(cli::sceneOptions({"out"}));
    RenderSettings ceir = cli::sceneSettings(args, RenderMode::CeirShallow);
    if (ceir.mode == RenderMode::Fvr)
        throw cli::UsageError("--mode: compare puts a CEIR or mono mode beside fvr");
    const int w = ceir.width, h = ceir.height;
    std::string outPng = args.get("out").value_or("compare.png");
    Volume vol = cli::loadScan(args);
    ceir.camera = cli::cameraFor(args, vol, w, h);
    RenderSettings fvr = ceir;
    fvr.mode = RenderMode::Fvr;

    vk::Context ctx(cli::contextOptions(args));
    Renderer renderer(ctx);
    renderer.setVolume(vol);
    Frame a = renderer.render(ceir);
    Frame b = renderer.render(fvr);

    double sum = 0.0, worst = 0.0;
    size_t both = 0;
    for (size_t p = 0; p < size_t(w) * size_t(h); ++p) {
        if (a.rgba[4 * p + 3] < 1.0f || b.rgba[4 * p + 3] < 0.5f) continue;
        ++both;
        for (int c = 0; c < 3; ++c) {
            double d = 255.0 * (double(a.rgba[4 * p + c]) - double(b.rgba[4 * p + c]));
            sum += d * d;
            worst = std::max(worst, std::abs(d));
        }
    }
    double rmse = both ? std::sqrt(sum / (3.0 * double(both))) : 0.0;

    std::vector<float> side(size_t(2 * w) * size_t(h) * 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 4; ++c) {
                size_t src = (size_t(y) * size_t(w) + size_t(x)) * 4 + size_t(c);
                side[(size_t(y) * size_t(2 * w) + size_t(x)) * 4 + size_t(c)] = a.rgba[src];
                side[(size_t(y) * size_t(2 * w) + size_t(w + x)) * 4 + size_t(c)] = b.rgba[src];
            }
    cli::Outputs outputs;
    writePng(outputs.stage(outPng), 2 * w, h, encodeSrgb8(side));
    outputs.commit();

    double ta = a.timings.empty() ? 0.0 : a.timings.front().ms,
           tb = b.timings.empty() ? 0.0 : b.timings.front().ms;
    std::printf("wrote %s (%dx%d: %s left, fvr right)\n", outPng.c_str(), 2 * w, h, modeName(ceir.mode));
    std::printf("gpu: %s (%s)\n", ctx.deviceName().c_str(), ctx.deviceType());
    std::printf("gpu time: %s %.3f ms, fvr %.3f ms (fvr / %s = %.2fx)\n", modeName(ceir.mode), ta, tb,
                modeName(ceir.mode), ta > 0 ? tb / ta : 0.0);
    std::printf("difference over %zu pixels both show: rmse %.2f/255, max %.2f/255 (linear RGB)\n", both,
                rmse, worst);
    return ctx.validationMessages() ? 3 : 0;
}

} // namespace iso::app
