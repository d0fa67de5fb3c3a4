#pragma once
// The presets of config/ (docs/formats.md "Presets"): arrays, processing
// configs, limit sets and channel maps, each a folder of NAME.json files. The
// one place napkin finds the configuration folder, lists a kind's presets and
// resolves what a user wrote (a preset's name or a file's path), so every
// front end and reader refuses the same mistake with the same sentence and
// exit status.
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "common/error.h"

namespace napkin::formats {

enum class PresetKind {
  kArray,             // config/arrays: accelerometer array definitions
  kProcessingConfig,  // config/processing: processing configs
  kLimits,            // config/limits: limit sets
  kChannelMap,        // config/channel-maps: channel code -> slot maps
};

// Every kind, in the order above.
std::span<const PresetKind> PresetKinds();

// "array", "processing", "limits", "channel-map": what napkin.presets(kind) takes.
std::string_view PresetKindName(PresetKind kind);

// The folder of `kind` under the configuration folder: "arrays", "processing", "limits", "channel-maps".
std::string_view PresetFolder(PresetKind kind);

// The kind named `name` (PresetKindName); throws UsageError listing the kinds when there is none.
PresetKind PresetKindNamed(std::string_view name);

// A name that is neither a readable file nor a preset of its kind: a usage
// error (exit status 2; the Python module raises napkin.InputError), one
// sentence listing the kind's presets.
class UnknownPresetError : public UsageError {
 public:
  using UsageError::UsageError;
};

// The configuration folder: $NAPKIN_CONFIG_DIR if set; else the config/ the
// build copies beside the program, or the one installed with the program or
// the Python module (<prefix>/share/napkin/config beside <prefix>/bin/napkin
// and <prefix>/lib/python3/dist-packages/napkin/); else the source tree's.
std::filesystem::path DefaultConfigDir();

// The presets of `kind` in `config_dir`, in name order (none when the folder is missing).
std::vector<std::string> PresetNames(PresetKind kind,
                                     const std::filesystem::path& config_dir = DefaultConfigDir());

// `name_or_path` if it names a regular file, else the preset of that name
// (<config_dir>/<folder>/<name>.json; a name holding '/' is a path only).
// Throws UnknownPresetError when it is neither: "\"NAME\" is neither a file
// nor a preset in DIR (presets: a, b, c)."
std::filesystem::path ResolvePreset(PresetKind kind, std::string_view name_or_path,
                                    const std::filesystem::path& config_dir = DefaultConfigDir());

}  // namespace napkin::formats
