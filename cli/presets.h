#pragma once
// Finding the JSON presets (config/arrays, config/processing,
// config/channel-maps) so `napkin` works from any directory.
#include <filesystem>
#include <string>

namespace napkin::cli {

// The config directory: $NAPKIN_CONFIG_DIR, else <binary dir>/config (copied
// there at build time), else <binary dir>/../share/napkin/config (installed).
// Throws InputError when none exists.
std::filesystem::path ConfigDir();

// A preset name ("denton-3222") from config/<kind>/<name>.json, or a path to
// a JSON file (anything containing '/' or ending in ".json"). Throws
// InputError naming the preset and listing the known ones when unknown.
std::filesystem::path ResolvePreset(const std::string& kind, const std::string& name_or_path);

}  // namespace napkin::cli
