#include "cli/presets.h"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <vector>

#include "engine/error.h"

namespace napkin::cli {
namespace fs = std::filesystem;

namespace {

std::string Noun(const std::string& kind) {
  if (kind == "arrays") return "array";
  if (kind == "channel-maps") return "channel map";
  if (kind == "processing") return "processing config";
  return kind;
}

fs::path BinaryDir() {
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  return error ? fs::current_path() : self.parent_path();
}

}  // namespace

fs::path ConfigDir() {
  if (const char* env = std::getenv("NAPKIN_CONFIG_DIR"); env != nullptr && *env != '\0') {
    if (fs::is_directory(env)) return env;
    throw InputError("NAPKIN_CONFIG_DIR '" + std::string(env) + "' is not a directory.");
  }
  const fs::path binary_dir = BinaryDir();
  for (const fs::path& candidate : {binary_dir / "config", binary_dir / ".." / "share" / "napkin" / "config"})
    if (fs::is_directory(candidate)) return fs::weakly_canonical(candidate);
  throw InputError("cannot find napkin's config directory next to " + binary_dir.string() +
                   " (set NAPKIN_CONFIG_DIR).");
}

fs::path ResolvePreset(const std::string& kind, const std::string& name_or_path) {
  const bool looks_like_path = name_or_path.find('/') != std::string::npos ||
                               (name_or_path.size() > 5 && name_or_path.ends_with(".json"));
  if (looks_like_path || fs::is_regular_file(name_or_path)) {
    if (!fs::is_regular_file(name_or_path))
      throw InputError(Noun(kind) + " file '" + name_or_path + "' does not exist.");
    return name_or_path;
  }
  const fs::path dir = ConfigDir() / kind;
  const fs::path preset = dir / (name_or_path + ".json");
  if (fs::is_regular_file(preset)) return preset;
  std::vector<std::string> known;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(dir, error))
    if (entry.path().extension() == ".json") known.push_back(entry.path().stem().string());
  std::sort(known.begin(), known.end());
  std::string list;
  for (const auto& name : known) list += (list.empty() ? "" : ", ") + name;
  throw InputError("unknown " + Noun(kind) + " '" + name_or_path + "' (known: " + list + ").");
}

}  // namespace napkin::cli
