#pragma once
// The catalogue is never an output (docs/formats.md "Output destinations").
#include <string>

namespace napkin::cli {

// Marks the --db catalogue and its SQLite side files (-wal, -shm, -journal,
// also under the name the catalogue's symbolic links resolve to, which SQLite
// uses) as files no output may replace (util/output_destination.h): every
// command's --out, --summary, --lsdyna, --results and demo file is refused
// when it is one of them by any name. main() calls it before any command runs.
void ProtectCatalogueFromOutput(const std::string& db_path);

}  // namespace napkin::cli
