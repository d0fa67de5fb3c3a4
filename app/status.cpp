#include "app/status.h"

#include <nlohmann/json.hpp>

namespace napkin::app {

CatalogueStatus ReadStatus(db::Catalogue& catalogue, const records::ResolvedConfig& config,
                           bool with_versions) {
  CatalogueStatus status;
  status.path = catalogue.path();
  status.config_name = config.record.name;
  status.config_hash = config.record.config_hash;
  const db::ConfigId id = catalogue.FindConfigByHash(config.record.config_hash).value_or(db::ConfigId{0});
  db::JobQueue queue(catalogue);
  status.counts = queue.ReadStatusCounts(id);
  if (with_versions) status.versions = queue.ReadVersionCounts();
  status.inbox_failures = catalogue.ReadInboxFailures();
  return status;
}

nlohmann::ordered_json StatusJson(const CatalogueStatus& status) {
  using Json = nlohmann::ordered_json;
  const db::StatusCounts& counts = status.counts;
  Json failures = Json::array();
  for (const db::JobFailure& failure : counts.failures)
    failures.push_back({{"test_id", failure.test_id}, {"error", failure.error}});
  Json inbox_failures = Json::array();
  for (const db::InboxFailure& failure : status.inbox_failures)
    inbox_failures.push_back({{"source", failure.source},
                              {"series", failure.series},
                              {"variant", failure.variant},
                              {"kind", failure.kind},
                              {"error", failure.error},
                              {"failed_at", failure.failed_at}});
  return Json{{"tests", counts.tests},
              {"done", counts.done},
              {"failed", counts.failed},
              {"pending", counts.pending},
              {"running", counts.running},
              {"salvaged", counts.salvaged},
              {"failures", std::move(failures)},
              // Additions (issue 43): the file and the config the counts are for.
              {"path", status.path},
              {"config", {{"name", status.config_name}, {"hash", status.config_hash}}},
              // Addition (issue 42): the inbox's tests that failed before their import.
              {"inbox_failures", std::move(inbox_failures)}};
}

}  // namespace napkin::app
