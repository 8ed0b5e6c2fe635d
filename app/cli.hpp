// Command-line parsing shared by the verbs: options are `--name value` or `--name=value`; every
// bad value becomes a UsageError whose message names the option and says what it expects.
#pragma once

#include "io/volume.hpp"
#include "render/renderer.hpp"
#include "scene/camera.hpp"
#include "vk/context.hpp"

#include <filesystem>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace iso::cli {

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

class Args {
  public:
    // `flags` are options without a value; every other --option takes one.
    Args(int argc, char** argv, int first, std::vector<std::string> flags);

    bool flag(const std::string& name) const;
    std::optional<std::string> get(const std::string& name) const;
    std::vector<std::string> all(const std::string& name) const; // a repeatable option
    std::string require(const std::string& name, const std::string& hint) const;
    const std::vector<std::string>& positional() const { return positional_; }
    // Rejects options the verb does not know, so a typo never passes silently.
    void allowOnly(const std::vector<std::string>& known) const;

  private:
    std::vector<std::string> flags_;
    std::multimap<std::string, std::string> values_;
    std::vector<std::string> positional_;
};

double parseNumber(const std::string& option, const std::string& text);
std::pair<int, int> parseSize(const std::string& option, const std::string& text); // "WxH"
std::vector<double> parseList(const std::string& option, const std::string& text, size_t count);

// The scan named by the first positional argument, with --raw-* options for headerless files.
Volume loadScan(const Args& args);
// --camera FILE, or a view that frames the whole volume.
Camera cameraFor(const Args& args, const Volume& vol, int width, int height);

// Files a verb writes are staged under temporary names and renamed into place only when all of
// them have been written, so a failure leaves neither partial files nor half a set behind.
class Outputs {
  public:
    ~Outputs(); // removes whatever was staged but not committed
    std::filesystem::path stage(const std::filesystem::path& finalPath);
    void commit();

  private:
    std::vector<std::pair<std::filesystem::path, std::filesystem::path>> staged_;
};

// The scene options shared by render, pick and compare: --iso, --size, --mode, --tf,
// --density-factor, --shading, --deep-reach, --step, --map-size, --crop, --peel, --seeds.
// Everything is checked before the scan is loaded, so mistakes are reported at once.
RenderSettings sceneSettings(const Args& args, RenderMode defaultMode);

// --device and --validate, for the verbs that use the GPU.
vk::ContextOptions contextOptions(const Args& args);

// Prints a verb's help (its text has one %s for the scan options) when --help was given.
bool printedHelp(const Args& args, const char* help);

// Options every scene verb takes: the scan, the view, the device and the scene settings.
std::vector<std::string> sceneOptions(std::vector<std::string> extra);

extern const char* kScanOptionsHelp;

} // namespace iso::cli
