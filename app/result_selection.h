#pragma once
// Which result of a test: resolving a stored config selector (`--config
// NAME|HASH-PREFIX` of query, compare and Python) or a processing config file
// (records::ResolveConfig, `--config` of run and export) to its catalogue
// record, and reading a result's kinematics.
#include <cstddef>
#include <string>
#include <vector>

#include "db/catalogue.h"
#include "engine/kinematics.h"
#include "records/config_record.h"

namespace napkin::app {

// A stored processing config named by a `--config NAME|HASH-PREFIX` selector
// (query, compare, report): the config whose name is `selector` (exactly
// one), else the one config whose hash starts with it (case-insensitive).
// Throws UsageError listing the catalogue's configs (name and hash) when none
// or several match.
db::ConfigRow ResolveConfigSelector(db::Catalogue& catalogue, const std::string& selector);

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

// `run`/`export --config` value (preset name or JSON path; empty: the default preset).
using records::ResolveConfig;
using records::ResolvedConfig;

}  // namespace napkin::app
