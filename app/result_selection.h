#pragma once
// Which result of a test (docs/architecture.md "Which result of a test"):
// a test has one result per processing config it was run under, and every
// front end names the one it means in one of three ways, each with one
// meaning:
//
//   Latest          the result written last (db::Catalogue::ReadLatestResultConfig;
//                   what the query views show without --config)
//   Stored{NAME}    the result under a config stored in the catalogue, named
//                   by its name or a hash prefix (ResolveConfigSelector; the
//                   `--config` of query and compare, napkin.Catalogue's config=)
//   Preset{PATH}    the result under the config a preset name or JSON file
//                   holds, found by its content hash (records::ResolveConfig;
//                   the `--config` of run, status, transform and export)
//
// Also: reading a result's kinematics.
#include <cstddef>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "db/catalogue.h"
#include "engine/kinematics.h"
#include "records/config_record.h"

namespace napkin::app {

struct Latest {};
struct Stored {
  std::string selector;  // a stored config's name or hash prefix
  // The option that gave it, as the front end spells it (its sentences name it).
  std::string option = "--config";
};
struct Preset {
  std::string name_or_path;  // a processing config preset name or JSON file; empty: the default preset
};
using ResultChoice = std::variant<Latest, Stored, Preset>;

// The config of `test`'s result that `choice` names, if the test has that
// result. Throws UsageError for a Stored selector that names no config or
// several (ResolveConfigSelector), InputError for a Preset that is no preset
// or readable file.
std::optional<db::ConfigId> FindResult(db::Catalogue& catalogue, db::TestId test, const ResultChoice& choice);

// A test's result: the test's key and the config of the result.
struct TestResult {
  db::TestId test;
  db::ConfigId config;
};

// The result of the test whose id is `test_id` that `choice` names. Throws
// NotFoundError "test 'T' is not in catalogue 'F'." (Catalogue::path names it);
// InputError "test 'T' has no results yet; run `napkin run` first." (Latest)
// or "test 'T' has no results for config 'C' yet; run `napkin run --config
// C` first." (Stored, Preset), and FindResult's errors.
TestResult ResultOf(db::Catalogue& catalogue, const std::string& test_id, const ResultChoice& choice);

// A stored processing config named by a `--config NAME|HASH-PREFIX` selector
// (query, compare, report): the config whose name is `selector` (exactly
// one), else the one config whose hash starts with it (case-insensitive).
// Throws UsageError naming `option` (as the front end spells it,
// app/request_options.h) and listing the catalogue's configs (name and hash)
// when none or several match.
db::ConfigRow ResolveConfigSelector(db::Catalogue& catalogue, const std::string& selector,
                                    const std::string& option = "--config");

// The one rule every config selector follows (`--config`, `compare
// --baseline` by config): the index in `configs` of the config named
// `selector`, else of the one whose hash starts with it (case-insensitive).
// Throws UsageError naming `option` when the selector is empty, when two or
// more configs have that name ("give a hash prefix instead") or start with
// that prefix, or when none matches (listing `configs`, introduced by
// `listed`, e.g. "the configs are").
std::size_t MatchConfigSelector(const std::vector<db::ConfigRow>& configs, const std::string& option,
                                const std::string& selector, const std::string& listed = "the configs are");

// The kinematics of the test's result under `config` (the caller knows the
// result exists), for every reader of derived channels (export, report,
// demo): the stored derived channels when the result has them (float64:
// bit-exact; float32: each value widened exactly), else (processing config
// storage.derived_channels "none") recomputed by records::RecomputeResult from
// the test's raw channels, initial state and array and the config decoded from
// its record -- the inputs and the computation `napkin run` computed the
// result with, so the recomputation equals a float64-stored result bit for
// bit (docs/formats.md "Derived-channel storage").
engine::Kinematics ReadResultKinematics(db::Catalogue& catalogue, db::TestId test, db::ConfigId config);

// The raw channels of a test's result (`export --format channels|recorded`,
// the report's overlay).
struct ResultChannels {
  engine::TestSignals signals;
  std::vector<std::string> repaired;  // the slots whose samples are the repaired ones
  // One line per salvaged channel saying what salvage did to it (and per
  // channel recorded as already filtered, which napkin's CSV cannot say).
  std::vector<std::string> notes;
};

// The raw channels the test's result under `config` was computed from: the
// recorded channels with each channel salvage repaired in its place, as the
// result's salvage record keeps it (docs/formats.md "Salvage record"), or
// with `recorded` the channels as recorded (the catalogue never changes
// them; `config` may then be none: the test has no result yet). Throws InputError naming the test and channel
// when a kept repaired channel's length is not the recorded one's, or when the result's repair was computed
// before repaired channels were kept (schema version 13).
ResultChannels ReadResultChannels(db::Catalogue& catalogue, db::TestId test,
                                  std::optional<db::ConfigId> config, bool recorded = false);

// `run`/`export --config` value (preset name or JSON path; empty: the default preset).
using records::ResolveConfig;
using records::ResolvedConfig;

}  // namespace napkin::app
