#pragma once
// A canonical text dump of what `napkin run` writes into a catalogue, so two
// catalogues compare with ==: one processed unsharded, one that merged the
// results files (or shard copies) of a sharded run (README "Batch runs").
//
// Tables, in this order: series, arrays, configs, tests, results, findings,
// result_conditioning, derived_channels, jobs; one line per row,
//   table|column=value|column=value...
// lines sorted within each table. Keys are replaced by what they name (test
// external id, config hash, series name, array definition hash), so the
// rows' keys need not agree; left out are every row's own key (`id`), the
// timestamps (columns ending in `_at`, `duration_s`) and who ran a job
// (`lease_owner`, `attempts`: a retried or resumed job computes the same
// result). Raw channels are left out (runs never write them). Values: NULL,
// integers in decimal, reals in C99 hex-float (%a, exact), text in single
// quotes with '\', newline and '|' escaped, BLOBs as `blob:<bytes>:<SHA-256>`
// of their bytes.
//
// Usage: C++ `db::CanonicalResultsDump(path) == db::CanonicalResultsDump(other)`;
// shell `napkin_results_dump CATALOGUE > a.txt` (target napkin_results_dump,
// build/dev/tests/napkin_results_dump) and `cmp a.txt b.txt`.
#include <string>

namespace napkin::db {

// The dump of the catalogue at `path`, opened read-only (never written).
// Throws InputError when it cannot be opened as a napkin catalogue.
std::string CanonicalResultsDump(const std::string& path);

}  // namespace napkin::db
