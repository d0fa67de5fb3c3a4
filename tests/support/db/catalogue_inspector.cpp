#include "tests/support/db/catalogue_inspector.h"

#include <cstdio>
#include <stdexcept>
#include <utility>

namespace napkin::db {

namespace {

std::string QuoteIdentifier(const std::string& name) {
  std::string quoted = "\"";
  for (const char c : name) {
    quoted += c;
    if (c == '"') quoted += '"';
  }
  return quoted + "\"";
}

}  // namespace

std::string CatalogueInspector::Dump() {
  Connection& connection = catalogue_.connection_;
  std::string dump = "user_version " + std::to_string(connection.PragmaInt("user_version")) + "\n";
  std::vector<std::pair<std::string, std::string>> tables;
  {
    auto select = connection.Prepare(
        "SELECT name, coalesce(sql, '') FROM sqlite_master WHERE type = 'table' ORDER BY name");
    while (select->Step()) tables.emplace_back(select->ColumnText(0), select->ColumnText(1));
  }
  {
    auto select = connection.Prepare(
        "SELECT type, name, coalesce(sql, '') FROM sqlite_master WHERE type <> 'table' ORDER BY type, name");
    while (select->Step())
      dump += select->ColumnText(0) + " " + select->ColumnText(1) + ": " + select->ColumnText(2) + "\n";
  }
  for (const auto& [name, sql] : tables) {
    dump.append("table ").append(name).append(": ").append(sql).append("\n");
    // A one-off statement per table: table names are identifiers, quoted.
    Statement rows(connection.handle(), "SELECT * FROM " + QuoteIdentifier(name) + " ORDER BY rowid");
    while (rows.Step()) {
      dump += " ";
      for (int c = 0; c < rows.ColumnCount(); ++c) {
        dump += c == 0 ? "(" : ", ";
        switch (rows.ColumnType(c)) {
          case SQLITE_NULL:
            dump += "NULL";
            break;
          case SQLITE_INTEGER:
            dump += std::to_string(rows.ColumnInt64(c));
            break;
          case SQLITE_FLOAT: {
            char text[32];
            std::snprintf(text, sizeof text, "%a", rows.ColumnDouble(c));  // exact
            dump += text;
            break;
          }
          case SQLITE_TEXT:
            dump += "'" + rows.ColumnText(c) + "'";
            break;
          default: {
            static constexpr char kHex[] = "0123456789abcdef";
            dump += "x'";
            for (const std::byte byte : rows.ColumnBlob(c)) {
              dump += kHex[static_cast<unsigned>(byte) >> 4];
              dump += kHex[static_cast<unsigned>(byte) & 0xf];
            }
            dump += "'";
          }
        }
      }
      dump += ")\n";
    }
  }
  return dump;
}

std::vector<SeriesRow> CatalogueInspector::ReadAllSeries() {
  auto select = catalogue_.connection_.Prepare("SELECT id, name, description FROM series ORDER BY name");
  std::vector<SeriesRow> all;
  while (select->Step())
    all.push_back({SeriesId{select->ColumnInt64(0)}, select->ColumnText(1), select->ColumnText(2)});
  return all;
}

std::optional<std::string> CatalogueInspector::ReadResultSolver(TestId test, ConfigId config) {
  auto select =
      catalogue_.connection_.Prepare("SELECT solver FROM results WHERE test_id = ?1 AND config_id = ?2");
  select->BindAll(test, config);
  if (!select->Step()) return std::nullopt;
  return select->ColumnText(0);
}

std::vector<SummaryRow> CatalogueInspector::ReadAllSummaries(const TestFilter& filter) {
  std::vector<SummaryRow> rows;
  for (const TestRow& test : catalogue_.ReadAllTests(filter)) {
    const std::optional<ConfigId> latest = catalogue_.ReadLatestResultConfig(test.id);
    if (!latest) continue;
    SummaryRow row{test.external_id, test.series, test.variant, *catalogue_.ReadSummary(test.id, *latest)};
    row.summary.findings.clear();
    rows.push_back(std::move(row));
  }
  return rows;
}

std::int64_t CatalogueInspector::Scalar(const std::string& sql) {
  auto select = catalogue_.connection_.Prepare(sql);
  select->Step();
  return select->ColumnInt64(0);
}

std::int64_t CatalogueInspector::CountRows(const std::string& table) {
  return Scalar("SELECT count(*) FROM " + QuoteIdentifier(table));
}

std::int64_t CatalogueInspector::CountTestsWithResults() {
  return Scalar("SELECT count(DISTINCT test_id) FROM results");
}

std::int64_t CatalogueInspector::CountJobsInState(const std::string& state) {
  auto select = catalogue_.connection_.Prepare("SELECT count(*) FROM jobs WHERE state = ?1");
  select->Bind(1, state);
  select->Step();
  return select->ColumnInt64(0);
}

std::int64_t CatalogueInspector::CountDoneJobsClaimedOnce() {
  return Scalar("SELECT count(*) FROM jobs WHERE attempts = 1 AND state = 'done'");
}

std::int64_t CatalogueInspector::CountDistinctLeaseOwners() {
  return Scalar("SELECT count(DISTINCT lease_owner) FROM jobs");
}

std::int64_t CatalogueInspector::CountResultsWithoutDoneJob() {
  return Scalar(
      "SELECT count(*) FROM results AS r WHERE NOT EXISTS (SELECT 1 FROM jobs AS j WHERE "
      "j.test_id = r.test_id AND j.config_id = r.config_id AND j.state = 'done')");
}

std::int64_t CatalogueInspector::CountIncompleteOrOrphanDerivedChannelSets(int channels_per_result) {
  auto select = catalogue_.connection_.Prepare(
      "SELECT count(*) FROM (SELECT test_id, config_id, count(*) AS n FROM derived_channels "
      "GROUP BY test_id, config_id) AS d WHERE d.n <> ?1 OR NOT EXISTS (SELECT 1 FROM results AS r "
      "WHERE r.test_id = d.test_id AND r.config_id = d.config_id)");
  select->Bind(1, channels_per_result);
  select->Step();
  return select->ColumnInt64(0);
}

std::vector<std::pair<std::string, std::int64_t>> CatalogueInspector::ReadDerivedChannelSizes(
    TestId test, ConfigId config) {
  auto select = catalogue_.connection_.Prepare(
      "SELECT name, length(samples) FROM derived_channels WHERE test_id = ?1 AND config_id = ?2 ORDER BY "
      "name");
  select->BindAll(test, config);
  std::vector<std::pair<std::string, std::int64_t>> sizes;
  while (select->Step()) sizes.emplace_back(select->ColumnText(0), select->ColumnInt64(1));
  return sizes;
}

std::vector<std::int64_t> CatalogueInspector::ReadJobAttempts(ConfigId config) {
  auto select =
      catalogue_.connection_.Prepare("SELECT attempts FROM jobs WHERE config_id = ?1 ORDER BY test_id");
  select->Bind(1, config);
  std::vector<std::int64_t> attempts;
  while (select->Step()) attempts.push_back(select->ColumnInt64(0));
  return attempts;
}

std::optional<std::string> CatalogueInspector::ReadResultVersion(TestId test, ConfigId config) {
  auto select = catalogue_.connection_.Prepare(
      "SELECT napkin_version FROM results WHERE test_id = ?1 AND config_id = ?2");
  select->BindAll(test, config);
  if (!select->Step()) throw std::logic_error("ReadResultVersion: no result for this test and config");
  return select->ColumnOptionalText(0);
}

std::optional<std::string> CatalogueInspector::ReadJobVersion(TestId test, ConfigId config) {
  auto select =
      catalogue_.connection_.Prepare("SELECT napkin_version FROM jobs WHERE test_id = ?1 AND config_id = ?2");
  select->BindAll(test, config);
  if (!select->Step()) throw std::logic_error("ReadJobVersion: no job for this test and config");
  return select->ColumnOptionalText(0);
}

void CatalogueInspector::SetResultVersion(TestId test, ConfigId config,
                                          const std::optional<std::string>& version) {
  auto update = catalogue_.connection_.Prepare(
      "UPDATE results SET napkin_version = ?3 WHERE test_id = ?1 AND config_id = ?2");
  update->BindAll(test, config, version);
  update->Execute();
  if (catalogue_.connection_.Changes() != 1)
    throw std::logic_error("SetResultVersion: no result for this test and config");
}

}  // namespace napkin::db
