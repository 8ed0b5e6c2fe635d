// isoscope: exact isosurface ray casting of CT and MRI scans on Vulkan.
#include "cli.hpp"

#include "io/volume.hpp"
#include "vk/check.hpp"

#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

namespace iso::app {
int renderVerb(int argc, char** argv);
int infoVerb(int argc, char** argv);
int devicesVerb(int argc, char** argv);
int pickVerb(int argc, char** argv);
int compareVerb(int argc, char** argv);
} // namespace iso::app

namespace {

const char* kHelp = R"(isoscope: exact isosurface rendering of CT and MRI scans (Vulkan compute)

Usage: isoscope VERB [options]

Verbs:
  render    render an isosurface of a scan to a PNG (and depth / voxel-id buffers)
  compare   render one view with CEIR and with full volume rendering, report time and difference
  pick      which voxel cell a pixel hits (--at x,y), or all cells in a rectangle (--rect)
  info      print a scan's dimensions, spacing, orientation, value range and histogram
  devices   list the Vulkan devices isoscope can use

Examples:
  isoscope info data/headsq_quarter.nhdr
  isoscope render data/headsq_quarter.nhdr --iso 500 --out skin.png
  isoscope render data/headsq_quarter.nhdr --iso 1150 --mode mono --size 1024x768 --out bone.png
  isoscope compare data/headsq_quarter.nhdr --iso 500 --size 256x256 --out compare.png
  isoscope pick data/headsq_quarter.nhdr --iso 500 --size 256x256 --at 128,128

Run 'isoscope VERB --help' for a verb's options. Every verb that uses the GPU takes
--device NAME (or ISOSCOPE_DEVICE=NAME): an index or part of a name from 'isoscope devices';
by default a discrete GPU is preferred, then an integrated one, then a CPU implementation
such as lavapipe. --validate (or ISOSCOPE_VALIDATE=1) turns on the Vulkan validation layers.
)";

} // namespace

int main(int argc, char** argv) {
    if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") ||
        !std::strcmp(argv[1], "help")) {
        std::fputs(kHelp, stdout);
        return argc < 2 ? 2 : 0;
    }
    std::string verb = argv[1];
    try {
        if (verb == "render") return iso::app::renderVerb(argc, argv);
        if (verb == "info") return iso::app::infoVerb(argc, argv);
        if (verb == "devices") return iso::app::devicesVerb(argc, argv);
        if (verb == "pick") return iso::app::pickVerb(argc, argv);
        if (verb == "compare") return iso::app::compareVerb(argc, argv);
        std::fprintf(stderr, "isoscope: unknown verb '%s' (run 'isoscope --help')\n", verb.c_str());
        return 2;
    } catch (const iso::cli::UsageError& e) {
        std::fprintf(stderr, "isoscope %s: %s\n", verb.c_str(), e.what());
        return 2;
    } catch (const iso::InputError& e) {
        std::fprintf(stderr, "isoscope %s: %s\n", verb.c_str(), e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "isoscope %s: %s\n", verb.c_str(), e.what());
        return 1;
    }
}
