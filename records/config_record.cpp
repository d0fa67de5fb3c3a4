#include "records/config_record.h"

#include <filesystem>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "formats/array_json.h"
#include "formats/presets.h"
#include "formats/processing_config_json.h"
#include "util/sha256.h"

namespace napkin::records {

db::ConfigRow MakeConfigRecord(const engine::ProcessingConfig& config, const std::string& name) {
  db::ConfigRow record;
  record.name = name;
  record.config_json = formats::CanonicalProcessingConfig(config);
  record.config_hash = util::Sha256Hex(record.config_json);
  return record;
}

engine::ProcessingConfig DecodeConfigRecord(const db::ConfigRow& record) {
  const std::string source = "config '" + record.name + "' of the catalogue";
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(record.config_json);
  } catch (const nlohmann::json::parse_error&) {
    throw InputError(source + " is not valid JSON.");
  }
  return formats::ParseProcessingConfig(json, source);
}

std::filesystem::path ProcessingConfigPath(const std::string& name_or_path,
                                           const std::filesystem::path& config_dir) {
  return formats::ResolvePreset(formats::PresetKind::kProcessingConfig,
                                name_or_path.empty() ? "default" : name_or_path, config_dir);
}

ResolvedConfig ResolveConfig(const std::string& name_or_path) {
  const std::filesystem::path path = ProcessingConfigPath(name_or_path, formats::DefaultConfigDir());
  ResolvedConfig resolved;
  resolved.config = formats::ReadProcessingConfig(path);
  resolved.record = MakeConfigRecord(resolved.config, path.stem().string());
  return resolved;
}

}  // namespace napkin::records
