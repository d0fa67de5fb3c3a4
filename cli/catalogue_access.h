#pragma once
// What the catalogue commands share: opening the --db catalogue and
// resolving the --config processing configuration to its catalogue record
// (records::ResolveConfig).
#include <string>

#include "cli/command.h"
#include "db/catalogue.h"
#include "records/config_record.h"

namespace napkin::cli {

db::Catalogue OpenCatalogue(const GlobalOptions& global, bool read_only = false);

// `--config` value (preset name or JSON path; empty: the default preset).
using records::ResolveConfig;
using records::ResolvedConfig;

}  // namespace napkin::cli
