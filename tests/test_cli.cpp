// The isoscope command line on bad input: one clear line naming the file and the problem, a
// non-zero exit, and no output file left behind.
#include "io/volume.hpp"
#include "oracle/oracle.hpp"
#include "scene/camera.hpp"

#include "temp_dir.hpp"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

struct Run {
    int status;
    std::string err;
    std::string out;
};

Run runApp(const std::string& args) {
    static int calls = 0;
    fs::path errFile = fs::temp_directory_path() / ("isoscope-cli-stderr-" + std::to_string(::getpid()) +
                                                    "-" + std::to_string(calls++) + ".txt");
    fs::path outFile = errFile;
    outFile += ".out";
    std::string cmd = std::string("'") + ISOSCOPE_APP + "' " + args + " >'" + outFile.string() + "' 2>'" +
                      errFile.string() + "'";
    int raw = std::system(cmd.c_str());
    auto slurp = [](const fs::path& f) {
        std::ifstream in(f);
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        fs::remove(f);
        return text;
    };
    std::string err = slurp(errFile);
    return {WIFEXITED(raw) ? WEXITSTATUS(raw) : 128, err, slurp(outFile)};
}

void checkRejected(const std::string& args, const std::string& mustMention, const fs::path& out) {
    Run r = runApp(args + " --out '" + out.string() + "'");
    INFO("isoscope " << args << "\nstderr: " << r.err);
    CHECK(r.status != 0);
    CHECK(r.status < 128); // an error exit, not a crash
    CHECK(r.err.find(mustMention) != std::string::npos);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1); // exactly one line
    CHECK_FALSE(fs::exists(out));
    for (const auto& e : fs::directory_iterator(out.parent_path()))
        CHECK(e.path().filename().string().find("isoscope-tmp") == std::string::npos);
}

const std::string kNrrdHead = "NRRD0004\ndimension: 3\nencoding: raw\nendian: little\n";

} // namespace

TEST_CASE("cli: bad input gets one clear line, a non-zero exit and no output") {
    iso::test::TempDir dir("cli");
    fs::path out = dir.path / "out.png";
    SUBCASE("truncated raw data") {
        auto f =
            dir.write("trunc.nrrd", kNrrdHead + "type: short\nsizes: 4 4 4\n\n" + std::string(100, '\1'));
        checkRejected("render '" + f.string() + "' --iso 1", "trunc.nrrd", out);
    }
    SUBCASE("dims whose product overflows") {
        auto f =
            dir.write("huge.nrrd", kNrrdHead + "type: uchar\nsizes: 4294967295 4294967295 4294967295\n\n");
        checkRejected("render '" + f.string() + "' --iso 1", "huge.nrrd", out);
    }
    SUBCASE("an unknown voxel type") {
        auto f = dir.write("type.nrrd", kNrrdHead + "type: complex\nsizes: 2 2 2\n\n" + std::string(8, '\0'));
        checkRejected("render '" + f.string() + "' --iso 1", "type.nrrd", out);
    }
    SUBCASE("a missing detached data file") {
        auto f = dir.write("detached.nhdr", kNrrdHead + "type: uchar\nsizes: 2 2 2\ndata file: gone.raw\n\n");
        checkRejected("render '" + f.string() + "' --iso 1", "gone.raw", out);
    }
    SUBCASE("a directory given as the scan") {
        checkRejected("render '" + dir.path.string() + "' --iso 1", dir.path.filename().string(), out);
    }
    SUBCASE("an empty file") {
        auto f = dir.write("empty.nrrd", "");
        checkRejected("render '" + f.string() + "' --iso 1", "empty.nrrd", out);
    }
    SUBCASE("an isovalue that is not a number") {
        auto f = dir.write("ok.nrrd", kNrrdHead + "type: uchar\nsizes: 2 2 2\n\n" + std::string(8, '\0'));
        checkRejected("render '" + f.string() + "' --iso skin", "--iso", out);
    }
    SUBCASE("a bad camera file") {
        auto f = dir.write("ok.nrrd", kNrrdHead + "type: uchar\nsizes: 2 2 2\n\n" + std::string(8, '\0'));
        auto cam = dir.write("cam.json", "{\"eye\": [0,0,1]}");
        checkRejected("render '" + f.string() + "' --iso 1 --camera '" + cam.string() + "'", "cam.json", out);
    }
    SUBCASE("an unknown option") {
        auto f = dir.write("ok.nrrd", kNrrdHead + "type: uchar\nsizes: 2 2 2\n\n" + std::string(8, '\0'));
        checkRejected("render '" + f.string() + "' --iso 1 --colour red", "--colour", out);
    }
}

TEST_CASE("cli: help teaches every verb") {
    for (const char* verb : {"render", "info", "devices"}) {
        Run r = runApp(std::string(verb) + " --help");
        CHECK(r.status == 0);
    }
    CHECK(runApp("--help").status == 0);
    CHECK(runApp("frobnicate").status != 0);
}

TEST_CASE("cli: pick reports the cell the oracle's ray hits") {
    const fs::path src = ISOSCOPE_SOURCE_DIR;
    const std::string scan = (src / "data/headsq_quarter.nhdr").string();
    const std::string camFile = (src / "data/headsq_quarter.camera.json").string();
    iso::Volume vol = iso::loadVolume(scan);
    iso::Camera cam = iso::loadCamera(camFile);
    iso::oracle::Options opt;
    opt.iso = 500.0;
    for (auto [x, y] : {std::pair{32, 30}, std::pair{20, 40}, std::pair{5, 5}}) {
        Run r = runApp("pick '" + scan + "' --iso 500 --size 64x64 --camera '" + camFile + "' --at " +
                       std::to_string(x) + "," + std::to_string(y) + " --validate");
        INFO("pixel " << x << "," << y << ": " << r.out << r.err);
        REQUIRE(r.status == 0);
        auto j = nlohmann::json::parse(r.out);
        iso::oracle::Hit ref = iso::oracle::trace(vol, iso::primaryRay(cam, 64, 64, x, y), opt);
        REQUIRE(j.at("hit").get<bool>() == ref.hit);
        if (!ref.hit) continue;
        CHECK(j.at("id").get<uint64_t>() == ref.cellId);
        CHECK(j.at("ijk")[0].get<uint32_t>() == ref.cell[0]);
        CHECK(j.at("ijk")[2].get<uint32_t>() == ref.cell[2]);
        CHECK(std::abs(j.at("t").get<double>() - ref.t) < 1e-3 * vol.spacing.z);
        CHECK(std::abs(j.at("value").get<double>() - 500.0) < 0.5);
    }
    Run rect =
        runApp("pick '" + scan + "' --iso 500 --size 64x64 --camera '" + camFile + "' --rect 28,28,36,36");
    REQUIRE(rect.status == 0);
    auto ids = nlohmann::json::parse(rect.out).at("ids").get<std::vector<uint64_t>>();
    CHECK(ids.size() > 4);
    CHECK(std::is_sorted(ids.begin(), ids.end()));
    CHECK(std::adjacent_find(ids.begin(), ids.end()) == ids.end());
}
