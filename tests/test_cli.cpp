// The isoscope command line on bad input: one clear line naming the file and the problem, a
// non-zero exit, and no output file left behind.
#include <doctest/doctest.h>

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
};

Run runApp(const std::string& args) {
    static int calls = 0;
    fs::path errFile = fs::temp_directory_path() /
                       ("isoscope-cli-stderr-" + std::to_string(::getpid()) + "-" + std::to_string(calls++) + ".txt");
    std::string cmd = std::string("'") + ISOSCOPE_APP + "' " + args + " >/dev/null 2>'" + errFile.string() + "'";
    int raw = std::system(cmd.c_str());
    std::ifstream in(errFile);
    std::string err((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    fs::remove(errFile);
    return {WIFEXITED(raw) ? WEXITSTATUS(raw) : 128, err};
}

struct TempDir {
    fs::path path;
    TempDir() {
        path = fs::temp_directory_path() / ("isoscope-cli-" + std::to_string(::getpid()));
        fs::create_directories(path);
    }
    ~TempDir() { fs::remove_all(path); }
    fs::path write(const std::string& name, const std::string& content) const {
        std::ofstream(path / name, std::ios::binary) << content;
        return path / name;
    }
};

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
    TempDir dir;
    fs::path out = dir.path / "out.png";
    SUBCASE("truncated raw data") {
        auto f = dir.write("trunc.nrrd", kNrrdHead + "type: short\nsizes: 4 4 4\n\n" + std::string(100, '\1'));
        checkRejected("render '" + f.string() + "' --iso 1", "trunc.nrrd", out);
    }
    SUBCASE("dims whose product overflows") {
        auto f = dir.write("huge.nrrd", kNrrdHead + "type: uchar\nsizes: 4294967295 4294967295 4294967295\n\n");
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
    SUBCASE("a directory given as the scan") { checkRejected("render '" + dir.path.string() + "' --iso 1", dir.path.filename().string(), out); }
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
