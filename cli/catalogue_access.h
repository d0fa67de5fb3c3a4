#pragma once
// What the catalogue commands share: opening the --db catalogue and
// resolving the --config processing configuration to its catalogue record
// (records::ResolveConfig).
#include <string>

#include "cli/command.h"
#include "db/catalogue.h"
#include "records/config_record.h"

namespace napkin::cli {

// Opens --db; for writing (read_only false) after SQLite's quick_check, so a
// damaged catalogue is refused before anything is written into it.
db::Catalogue OpenCatalogue(const GlobalOptions& global, bool read_only = false);

// A stored processing config named by a `--config NAME|HASH-PREFIX` selector
// (query, compare, report): the config whose name is `selector` (exactly
// one), else the one config whose hash starts with it (case-insensitive).
// Throws UsageError listing the catalogue's configs (name and hash) when none
// or several match.
db::ConfigRecord ResolveConfigSelector(db::Catalogue& catalogue, const std::string& selector);

// `run`/`export --config` value (preset name or JSON path; empty: the default preset).
using records::ResolveConfig;
using records::ResolvedConfig;

}  // namespace napkin::cli
