#pragma once
// Processing configurations as catalogue records: the canonical JSON
// (formats::CanonicalProcessingConfig) and its SHA-256, which identify the
// results computed with the configuration.
#include <filesystem>
#include <string>

#include "db/catalogue.h"
#include "engine/processing.h"

namespace napkin::records {

// The record of `config` under `name`: name, canonical JSON and its SHA-256.
db::ConfigRow MakeConfigRecord(const engine::ProcessingConfig& config, const std::string& name);

// Parses a stored configuration back from its canonical JSON: the
// configuration the results under `record` were computed with. Throws
// InputError naming the config when the JSON is malformed or out of range.
engine::ProcessingConfig DecodeConfigRecord(const db::ConfigRow& record);

// A processing configuration and its record: what `napkin run` processes
// with (jobs::RunScheduler), the storage choice of its derived channels
// included (config.storage).
struct ResolvedConfig {
  engine::ProcessingConfig config;
  db::ConfigRow record;  // name, canonical JSON and its SHA-256
};

// The file of a processing configuration given by preset name (in
// `config_dir`) or JSON path; empty is the "default" preset. Throws
// InputError naming the presets where there is no such file.
std::filesystem::path ProcessingConfigPath(const std::string& name_or_path,
                                           const std::filesystem::path& config_dir);

// A processing configuration given by preset name or JSON path (empty: the
// "default" preset), read and checked, with its record named after the
// file's stem. Throws InputError naming the file and the key at fault.
ResolvedConfig ResolveConfig(const std::string& name_or_path);

}  // namespace napkin::records
