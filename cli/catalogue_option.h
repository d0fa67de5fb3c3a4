#pragma once
// Opening the --db catalogue, as every catalogue command does.
#include "cli/command.h"
#include "db/catalogue.h"

namespace napkin::cli {

// Opens --db; for writing (read_only false) after SQLite's quick_check, so a
// damaged catalogue is refused before anything is written into it.
db::Catalogue OpenCatalogue(const GlobalOptions& global, bool read_only = false);

}  // namespace napkin::cli
