#pragma once
// What the catalogue commands share: opening the --db catalogue and
// resolving the --config processing configuration to its catalogue record.
#include <string>

#include "cli/command.h"
#include "db/catalogue.h"
#include "engine/processing.h"

namespace napkin::cli {

db::Catalogue OpenCatalogue(const GlobalOptions& global, bool read_only = false);

struct ResolvedConfig {
  engine::ProcessingConfig config;
  db::ConfigRecord record;  // name, canonical JSON and its SHA-256
};

// `--config` value (preset name or JSON path; empty: the default preset).
ResolvedConfig ResolveConfig(const std::string& name_or_path);

}  // namespace napkin::cli
