#pragma once
// The work of `napkin import` as functions tests call: find the tests in the
// given paths, read each one, and store it (array, test record, raw
// channels) in one catalogue transaction per test, skipping content that is
// already in the catalogue. A folder import that is interrupted keeps every
// finished test; rerunning it skips those and imports the rest.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/error.h"
#include "db/catalogue.h"
#include "ingest/discovery.h"

namespace napkin::ingest {

// The name `compare` and `report` give the group of tests without a variant;
// import refuses it as a --variant, so the two are never pooled
// (docs/formats.md "napkin compare").
inline constexpr const char* kNoVariantGroup = "(none)";

struct ImportOptions {
  // Preset name or array JSON path. Empty: each input's ISO/TS 13499 channel
  // codes define its array where they can (ingest/array_from_codes.h); an
  // input whose codes define none is refused naming `array_option`.
  std::string array;
  std::string array_option = "--array";  // how the front end names the array in sentences
  std::optional<std::string> series;
  std::optional<std::string> variant;  // never kNoVariantGroup
  // Only when exactly one test is found. Without it: the files' own id (DTS SLICEWare's Test ID),
  // else the input's name (ImportInput::name).
  std::optional<std::string> test_id;
  std::vector<double> orientation_rad;  // phi, theta, psi (empty: 0, 0, 0)
  // vx, vy, vz fixed frame (empty: the UDS-1992 INIVEL of the CG channels
  // rotated by the orientation, else 0; docs/formats.md "UDS-1992 input").
  std::vector<double> initial_velocity_mps;
  // Preset name or path. Empty: the "default" map for ISO-MME folders, and
  // for UDS-1992 groups the report's Table 2-1 order (nine files by name, an
  // array of Table 2-1 slots), else the "default" map.
  std::string channel_map;
  // `--column SLOT=NAME` (CSV columns feeding slots; they override the
  // channel map's "column" entries).
  std::vector<std::string> csv_columns;
  // `--position P`: only the dummy head at this position (docs/formats.md
  // "Several dummies in one test"). Without it every head found is imported,
  // as TEST/<position> when there are several.
  std::optional<std::string> position;
  // A test of the same id imported from the same source path whose content
  // has changed since is replaced by the new content (its results, findings
  // and ratings go with the old content): the inbox of `napkin serve`, where
  // a recording that paused longer than --settle was imported half-written
  // and then went on. Without it such a test is refused (another --test-id).
  bool supersede_changed_source = false;
};

enum class ImportOutcome { kImported, kSkipped, kFailed };

// One result per catalogue test: an input holding several dummy heads gives one per head.
struct ImportResult {
  ImportOutcome outcome = ImportOutcome::kFailed;
  std::string test_id;
  std::string message;                // one sentence: the skip notice, or the error naming file and problem
  std::vector<std::string> warnings;  // e.g. ignored extra CSV columns
  // kImported only: the new content replaced the catalogue's older test of
  // this id and source (ImportOptions::supersede_changed_source).
  bool superseded = false;
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
// others still go ahead. Only input errors (InputError, an input file that
// cannot be read) fail a test: a database failure (disk full, lock timeout)
// and anything else (std::logic_error and the like, a bug in napkin;
// std::bad_alloc) throw after keeping the tests finished so far (the CLI
// reports an internal error, as for `run`).
ImportReport ImportTests(db::Catalogue& catalogue, const std::vector<std::string>& paths,
                         const ImportOptions& options, const ImportProgress& progress = {});

}  // namespace napkin::ingest
