#pragma once
// Shared pieces of the Catalogue implementation (not part of the interface).
#include <optional>
#include <string>
#include <vector>

#include "db/catalogue.h"

namespace napkin::db {
struct JobScope;
}  // namespace napkin::db

namespace napkin::db::internal {

// WHERE terms selecting the tests (alias t, series alias s) of a TestFilter,
// bound by BindTestFilter to parameters ?1 (series), ?2 (variants) and ?3
// (external ids), each the one name or a JSON array of several. Other
// parameters of such statements start at ?10.
// Only the terms of the fields the filter sets are written ("1" when it sets
// none): a term "?1 IS NULL OR s.name = ?1" hides the indexes from SQLite's
// planner, which then reads every test of the catalogue to select one series
// or a few named tests (docs/architecture.md "Catalogues of a million tests").
std::string TestFilterTerms(const TestFilter& filter);

// An SQL expression formatting the epoch seconds bound to `parameter` as ISO-8601 UTC.
inline std::string IsoTimestampSql(const std::string& parameter) {
  return "strftime('%Y-%m-%dT%H:%M:%fZ', " + parameter + ", 'unixepoch')";
}

// `values` as a JSON array of strings, for json_each(); nullopt when empty.
std::optional<std::string> JsonStringArray(const std::vector<std::string>& values);

// The results table's summary columns ("hic15, hic15_t1_s, ...", each with
// `prefix`): engine::SummaryFields(), in table order.
std::string SummaryColumnList(const std::string& prefix = "");

// Binds the fields `filter` sets (those TestFilterTerms wrote); the others stay unbound.
void BindTestFilter(Statement& statement, const TestFilter& filter);

// Whether SQLite's quick_check (every page and record well-formed, one read
// of the file; not the index contents) finds database `schema` of
// `connection` ("main", or the name of an ATTACHed file) sound. A file so
// damaged that the check itself fails (SQLITE_CORRUPT, SQLITE_NOTADB) is
// not sound either; any other failure is thrown.
bool PassesQuickCheck(Connection& connection, const std::string& schema = "main");

// The common table expression "scope AS (SELECT t.id AS test_id ...)" of
// the tests of a JobScope (db/job_queue.h), bound by BindJobScope to
// parameters ?1..?5; other parameters of such statements start at ?10.
std::string JobScopeCte(const JobScope& scope);
// " AND <the test in column `test_column` is in `scope`>", looked up by the
// test's key (empty for the whole catalogue), with JobScopeCte's parameters.
std::string InJobScope(const std::string& test_column, const JobScope& scope);
// Throws InputError for a shard other than I/N with 0 <= I < N.
void BindJobScope(Statement& statement, const JobScope& scope);

// The statements of db::JobQueue whose cost must not grow with the catalogue
// (tests/db/query_plan_test.cpp reads their plans): EnqueueMissing's (the
// up-to-date check: insert the missing jobs, queue the failed and stale ones
// again) and ClaimJobs' (?14 jobs after key ?15).
std::vector<std::string> EnqueueSql(const JobScope& scope);
std::string ClaimSql(const JobScope& scope);

}  // namespace napkin::db::internal
