#pragma once
// The catalogue and a command's own inputs are never an output (docs/formats.md
// "Output destinations").
#include <filesystem>
#include <string>

namespace napkin::app {

// Marks the --db catalogue and its SQLite side files (-wal, -shm, -journal,
// also under the name the catalogue's symbolic links resolve to, which SQLite
// uses) as files no output may replace (util/output_destination.h): every
// command's --out, --summary, --lsdyna, --results and demo file is refused
// when it is one of them by any name. main() calls it before any command runs.
void ProtectCatalogueFromOutput(const std::string& db_path);

// Marks a file the command reads (an input recording, array, config, channel
// map) as one no output of the same command may replace, by any name:
// refused as a usage error (exit 2) naming `what`, e.g. "the --array file". An empty path is skipped.
void ProtectInputFromOutput(const std::filesystem::path& input, const std::string& what);

}  // namespace napkin::app
