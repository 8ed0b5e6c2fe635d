// isoscope info: what a scan holds, to choose isovalues and check geometry before rendering.
#include "cli.hpp"

#include <algorithm>
#include <cstdio>

namespace iso::app {

int infoVerb(int argc, char** argv) {
    cli::Args args(argc, argv, 2, {"help", "raw-big-endian"});
    if (args.flag("help")) {
        std::printf("isoscope info SCAN [--bins N]\n\n"
                    "Prints dimensions, spacing, origin, directions (LPS), voxel type, value range and a\n"
                    "histogram of the values, to help choose an isovalue.\n\n"
                    "  --bins N   histogram bins (default 16)\n%s\n"
                    "Example:\n  isoscope info data/headsq_quarter.nhdr\n",
                    cli::kScanOptionsHelp);
        return 0;
    }
    args.allowOnly({"help", "bins", "raw-dims", "raw-type", "raw-spacing", "raw-big-endian"});
    double binsArg = cli::parseNumber("bins", args.get("bins").value_or("16"));
    if (binsArg < 1 || binsArg > 256 || binsArg != double(int(binsArg)))
        throw cli::UsageError("--bins: a whole number from 1 to 256");
    Volume vol = cli::loadScan(args);
    std::printf("scan:       %s\n", vol.source.c_str());
    std::printf("dims:       %u x %u x %u (%zu samples)\n", vol.dims[0], vol.dims[1], vol.dims[2],
                vol.sampleCount());
    std::printf("type:       %s (%zu bytes)\n", voxelTypeName(vol.type), vol.byteSize());
    std::printf("spacing:    %g %g %g\n", vol.spacing.x, vol.spacing.y, vol.spacing.z);
    std::printf("origin:     %g %g %g\n", vol.origin.x, vol.origin.y, vol.origin.z);
    for (int c = 0; c < 3; ++c)
        std::printf("direction %c: %g %g %g\n", "ijk"[c], vol.directions[c].x, vol.directions[c].y,
                    vol.directions[c].z);
    glm::dvec3 extent = vol.spacing * glm::dvec3(vol.dims[0] - 1.0, vol.dims[1] - 1.0, vol.dims[2] - 1.0);
    std::printf("extent:     %g x %g x %g\n", extent.x, extent.y, extent.z);
    std::printf("values:     %g .. %g\n", vol.valueMin, vol.valueMax);
    Histogram h = histogram(vol, int(binsArg));
    uint64_t peak = std::max<uint64_t>(1, *std::max_element(h.counts.begin(), h.counts.end()));
    double width = (h.hi - h.lo) / double(h.counts.size());
    std::printf("histogram:\n");
    for (size_t b = 0; b < h.counts.size(); ++b) {
        int bar = int(40.0 * double(h.counts[b]) / double(peak) + 0.5);
        std::printf("  %10.4g .. %-10.4g %10llu %s\n", h.lo + width * double(b), h.lo + width * double(b + 1),
                    (unsigned long long)h.counts[b], std::string(size_t(bar), '#').c_str());
    }
    return 0;
}

} // namespace iso::app
