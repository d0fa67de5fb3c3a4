#include "formats/presets.h"

#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <system_error>

#include "common/joined.h"

namespace napkin::formats {
namespace {

namespace fs = std::filesystem;

struct PresetKindRow {
  PresetKind kind;
  std::string_view name;
  std::string_view folder;
};

constexpr std::array<PresetKindRow, 4> kPresetKindTable = {{
    {PresetKind::kArray, "array", "arrays"},
    {PresetKind::kProcessingConfig, "processing", "processing"},
    {PresetKind::kLimits, "limits", "limits"},
    {PresetKind::kChannelMap, "channel-map", "channel-maps"},
}};

constexpr std::array<PresetKind, 4> kAllPresetKinds = {PresetKind::kArray, PresetKind::kProcessingConfig,
                                                       PresetKind::kLimits, PresetKind::kChannelMap};

const PresetKindRow& PresetKindRowOf(PresetKind kind) {
  return *std::find_if(kPresetKindTable.begin(), kPresetKindTable.end(),
                       [kind](const PresetKindRow& row) { return row.kind == kind; });
}

// An object of this library, whose address dladdr finds the file of.
const char kPresetsAnchor = 0;

// The folder of the program or shared object holding this code: the napkin
// executable, or the Python module's _napkin*.so (dladdr, glibc).
fs::path PresetsObjectDir() {
  Dl_info info{};
  if (::dladdr(&kPresetsAnchor, &info) == 0 || info.dli_fname == nullptr) return {};
  std::error_code error;
  const fs::path object = fs::canonical(info.dli_fname, error);
  return error ? fs::path() : object.parent_path();
}

}  // namespace

std::span<const PresetKind> PresetKinds() { return kAllPresetKinds; }

std::string_view PresetKindName(PresetKind kind) { return PresetKindRowOf(kind).name; }

std::string_view PresetFolder(PresetKind kind) { return PresetKindRowOf(kind).folder; }

PresetKind PresetKindNamed(std::string_view name) {
  for (const PresetKindRow& row : kPresetKindTable)
    if (row.name == name) return row.kind;
  throw UsageError("preset kind \"" + std::string(name) + "\" is not one of " +
                   Joined(kPresetKindTable, [](const PresetKindRow& row) { return std::string(row.name); }) +
                   ".");
}

fs::path DefaultConfigDir() {
  if (const char* dir = std::getenv("NAPKIN_CONFIG_DIR"); dir != nullptr && *dir != '\0') return dir;
  const fs::path object_dir = PresetsObjectDir();
  if (!object_dir.empty()) {
    // Beside the build's program; <prefix>/bin/napkin; <prefix>/lib/python3/dist-packages/napkin/_napkin.so.
    const std::array<fs::path, 3> candidates = {
        object_dir / "config", object_dir / ".." / "share" / "napkin" / "config",
        object_dir / ".." / ".." / ".." / ".." / "share" / "napkin" / "config"};
    std::error_code error;
    for (const fs::path& candidate : candidates)
      if (fs::is_directory(candidate / "arrays", error)) return candidate.lexically_normal();
  }
  return NAPKIN_BUILD_CONFIG_DIR;
}

std::vector<std::string> PresetNames(PresetKind kind, const fs::path& config_dir) {
  std::vector<std::string> names;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(config_dir / PresetFolder(kind), error))
    if (entry.path().extension() == ".json") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

fs::path ResolvePreset(PresetKind kind, std::string_view name_or_path, const fs::path& config_dir) {
  std::error_code error;
  const fs::path as_path(name_or_path);
  if (!name_or_path.empty() && fs::is_regular_file(as_path, error)) return as_path;
  const fs::path folder = config_dir / PresetFolder(kind);
  // A name with a '/' is a path that is not there, never a preset outside the folder.
  if (!name_or_path.empty() && name_or_path.find('/') == std::string_view::npos) {
    fs::path preset = folder / (std::string(name_or_path) + ".json");
    if (fs::is_regular_file(preset, error)) return preset;
  }
  throw UnknownPresetError("\"" + std::string(name_or_path) + "\" is neither a file nor a preset in " +
                           folder.string() + " (presets: " + Joined(PresetNames(kind, config_dir)) + ").");
}

}  // namespace napkin::formats
