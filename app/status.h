#pragma once
// The catalogue's state for one processing config (`napkin status`, the
// `catalogue` part of GET /api/v1/status, its /metrics gauges): one typed
// reading, rendered as the command's table and as the JSON object both the
// command (`--format json`) and the service print (docs/formats.md "Version
// string and provenance", docs/serve.md "HTTP API").
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "db/catalogue.h"
#include "db/job_queue.h"
#include "records/config_record.h"

namespace napkin::app {

struct CatalogueStatus {
  std::string path;         // the catalogue file, as given
  std::string config_name;  // the config the tests are counted for
  std::string config_hash;
  db::StatusCounts counts;  // the tests by state for that config, and the failures
  // Results and failures by the napkin version that computed them, for every
  // config: what `run --outdated` would recompute (read only when asked: the
  // command's table shows them).
  std::vector<db::VersionCount> versions;
  // Tests of `napkin serve --inbox` that failed before they were imported (a bad sidecar, a
  // folder name, an unreadable file; docs/serve.md "Inbox"): of no config, so always read.
  std::vector<db::InboxFailure> inbox_failures;
};

// The status of `catalogue` (its file named by Catalogue::path) for `config` (resolved from
// a preset or file before the catalogue is opened: records::ResolveConfig). A
// config never run on this catalogue has no key: every test is pending.
// `with_versions`: also the counts by napkin version.
CatalogueStatus ReadStatus(db::Catalogue& catalogue, const records::ResolvedConfig& config,
                           bool with_versions = false);

// The JSON object, keys in this order (README "napkin status"): tests, done,
// failed, pending, running, salvaged, failures ([{test_id, error}], by test
// id), path, config ({name, hash}), inbox_failures ([{source, series, variant, kind, error,
// failed_at}], by source).
nlohmann::ordered_json StatusJson(const CatalogueStatus& status);

}  // namespace napkin::app
