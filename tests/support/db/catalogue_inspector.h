#pragma once
// Test-only access to a catalogue: reads the product has no use for (a
// deterministic dump to compare catalogues, every series, a result's solver,
// every latest summary) and the raw-SQL checks of the tests, named for what
// they check. A friend of db::Catalogue, so the product's interface holds
// only what the product uses. The db tests may use connection() for their own
// SQL; tests elsewhere use the named helpers and write no SQL.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "db/catalogue.h"
#include "db/sqlite.h"
#include "engine/summary.h"

namespace napkin::db {

// One test's latest summary with its labels (query criteria).
struct SummaryRow {
  std::string test_id;  // external id
  std::optional<std::string> series;
  std::optional<std::string> variant;
  engine::TestSummary summary;  // without findings
};

// A view of a catalogue: it must not outlive it (a temporary one is refused).
class CatalogueInspector {
 public:
  explicit CatalogueInspector(Catalogue& catalogue) : catalogue_(catalogue) {}
  CatalogueInspector(Catalogue&&) = delete;

  // The catalogue's connection, for the db tests' own SQL.
  Connection& connection() { return catalogue_.connection_; }

  // Every table's schema and rows in a deterministic text form (rows in rowid
  // order, values type-tagged, BLOBs in hex): compare catalogues in tests.
  std::string Dump();
  // Every series, ordered by name.
  std::vector<SeriesRow> ReadAllSeries();
  // The solver that computed the test's result under `config`, if any.
  std::optional<std::string> ReadResultSolver(TestId test, ConfigId config);
  // Latest summary of every test in `filter` that has one, ordered by test id
  // (Catalogue::ReadLatestResultConfig and ReadSummary of each test).
  std::vector<SummaryRow> ReadAllSummaries(const TestFilter& filter = {});

  // ---- counts and job states for tests outside tests/db
  // Rows of `table` (a table name of the schema).
  std::int64_t CountRows(const std::string& table);
  // Distinct tests with at least one result row.
  std::int64_t CountTestsWithResults();
  // Jobs in `state` ("queued", "running", "done" or "failed").
  std::int64_t CountJobsInState(const std::string& state);
  // Done jobs that were claimed exactly once.
  std::int64_t CountDoneJobsClaimedOnce();
  // Distinct lease owners ever recorded on a job (done jobs keep theirs).
  std::int64_t CountDistinctLeaseOwners();
  // Result rows without a done job of the same test and config.
  std::int64_t CountResultsWithoutDoneJob();
  // (test, config) sets of derived channels that do not hold exactly
  // `channels_per_result` channels or have no result row.
  std::int64_t CountIncompleteOrOrphanDerivedChannelSets(int channels_per_result);
  // The derived channels stored for the test's result under `config`: name
  // and bytes of samples, in name order.
  std::vector<std::pair<std::string, std::int64_t>> ReadDerivedChannelSizes(TestId test, ConfigId config);
  // `attempts` of every job of `config`, in test key order.
  std::vector<std::int64_t> ReadJobAttempts(ConfigId config);

  // ---- provenance (schema/007_provenance.sql)
  // The napkin version recorded with the test's result under `config` (nullopt: NULL,
  // before version tracking). Throws std::logic_error when there is no such result.
  std::optional<std::string> ReadResultVersion(TestId test, ConfigId config);
  // The napkin version recorded with the test's job under `config` (nullopt: NULL).
  // Throws std::logic_error when there is no such job.
  std::optional<std::string> ReadJobVersion(TestId test, ConfigId config);
  // Marks the test's result under `config` as computed by `version` (nullopt: before
  // version tracking): stands for a result an older napkin wrote. Throws
  // std::logic_error when there is no such result.
  void SetResultVersion(TestId test, ConfigId config, const std::optional<std::string>& version);

 private:
  std::int64_t Scalar(const std::string& sql);

  Catalogue& catalogue_;
};

}  // namespace napkin::db
