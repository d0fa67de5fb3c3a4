#pragma once
// The work of `napkin import` as functions tests call: find the tests in the
// given paths, read each one, and store it (array, test record, raw
// channels) in one catalogue transaction per test, skipping content that is
// already in the catalogue. A folder import that is interrupted keeps every
// finished test; rerunning it skips those and imports the rest.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cli/array_record.h"
#include "db/catalogue.h"
#include "engine/array_geometry.h"
#include "engine/error.h"

namespace napkin::cli {

// Options that contradict each other (exit status 2, usage error), e.g.
// --test-id for paths that hold several tests.
class ImportUsageError : public InputError {
 public:
  using InputError::InputError;
};

enum class InputFormat { kCsv, kIsoMme, kUds1992 };
const char* InputFormatName(InputFormat format);  // "csv", "iso-mme", "uds-1992"

// One test found in the import paths.
struct ImportInput {
  InputFormat format = InputFormat::kCsv;
  // The default test id: file name without extension (CSV), folder name
  // (ISO-MME; the .mme file's stem when the .mme file itself was given), or
  // the shared stem of a UDS-1992 group (v0001.001 ... v0001.009 -> v0001).
  std::string name;
  // The CSV file or the ISO-MME test folder; for a UDS-1992 group
  // "<folder>/<stem>.*" (its files are in `files`).
  std::filesystem::path source;
  std::vector<std::filesystem::path> files;  // UDS-1992 group members, sorted by name
};

struct Discovery {
  std::vector<ImportInput> inputs;  // in path order; tests inside a folder sorted by name
  std::vector<std::string> errors;  // one sentence per path that holds no test
};

// Finds the tests in `paths`:
// - a file *.csv: one CSV test; *.mme: the ISO-MME test folder around it;
//   a file whose extension is three digits (.001): a UDS-1992 channel file,
//   grouped with the other given UDS-1992 files of its folder and stem;
// - a folder holding a *.mme file: one ISO-MME test;
// - any other folder: every test inside it, searched recursively (CSV files,
//   ISO-MME test folders, UDS-1992 stem groups; other files are ignored).
// A path that does not exist, an unrecognised file or a folder without any
// test is reported in `errors`.
Discovery DiscoverInputs(const std::vector<std::string>& paths);

struct ImportOptions {
  std::string array;  // preset name or array JSON path (required)
  std::optional<std::string> series;
  std::optional<std::string> variant;
  std::optional<std::string> test_id;        // only when exactly one test is found
  std::vector<double> orientation_rad;       // phi, theta, psi (empty: 0, 0, 0)
  std::vector<double> initial_velocity_mps;  // vx, vy, vz fixed frame (empty: 0)
  // Preset name or path. Empty: the "default" map for ISO-MME folders, and
  // the report's Table 2-1 order (nine files by name) for UDS-1992 groups.
  std::string channel_map;
};

enum class ImportOutcome { kImported, kSkipped, kFailed };

struct ImportResult {
  ImportOutcome outcome = ImportOutcome::kFailed;
  std::string test_id;
  std::string message;                // one sentence: the skip notice, or the error naming file and problem
  std::vector<std::string> warnings;  // e.g. ignored extra CSV columns
};

struct ImportReport {
  std::int64_t imported = 0;
  std::int64_t skipped = 0;
  std::int64_t failed = 0;            // inputs refused (nothing of them stored), discovery errors included
  std::vector<ImportResult> results;  // discovery errors first, then one per input in order

  // "imported 198 tests, skipped 2 already present[, 1 failed]."
  std::string SummaryLine() const;
};

// Called after each input: index of the finished input (1-based), number of
// inputs, and its result.
using ImportProgress = std::function<void(std::size_t done, std::size_t total, const ImportResult& result)>;

// Imports every test of `paths`. Options that concern all inputs (array,
// channel map, --test-id with several tests, numbers) are checked first and
// throw InputError before anything is stored. Then each input is read fully
// (before any write) and stored in its own transaction, or refused with its
// error recorded in the report (the catalogue keeps nothing of it); the
// others still go ahead. A database failure (disk full, lock timeout) throws
// after keeping the tests finished so far.
ImportReport ImportTests(db::Catalogue& catalogue, const std::vector<std::string>& paths,
                         const ImportOptions& options, const ImportProgress& progress = {});

// The content hash of an input: SHA-256 of the CSV file, of the ISO-MME
// folder's files (formats::HashPath), or of the UDS-1992 group's file hashes
// in name order.
std::string ContentHash(const ImportInput& input);

}  // namespace napkin::cli
