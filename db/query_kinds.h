#pragma once
// The query kinds: `napkin query KIND`, GET /api/v1/query/KIND and
// napkin.Catalogue.query(KIND) (docs/formats.md "Query filters"). One table,
// QueryKinds() in db/query_kinds.cpp, holds every kind: its name, what it
// lists, whether it needs a limit set, its columns and the SQL its rows are
// read from. The command line's help and choices, the service's route, the
// Python module's napkin.QUERY_KINDS and the error for an unknown kind all
// come from it (docs/developing.md "Adding a query kind").
#include <string>
#include <string_view>
#include <vector>

#include "engine/summary_fields.h"

namespace napkin::db {

// The kinds code names (each one row of QueryKinds()).
enum class QueryKind {
  kTests,
  kHic,
  kRotation,
  kCriteria,
  kQuality,
  kConditioning,
  kRisk,
  kCorrelation,
  kLimits
};

// A column of a query table that --where and --sort may name: a summary
// field (a number) or a label (text).
struct QueryField {
  std::string name;
  bool numeric = false;
};

// What a kind gives the test summary (GET /api/v1/tests/ID, docs/serve.md).
enum class TestSummaryPart {
  kNone,     // nothing (rows per channel: ask the query)
  kRow,      // the test's row, null without one
  kAllRows,  // every row of the test, a list (findings)
};

// One query kind.
struct QueryKindSpec {
  QueryKind kind;
  std::string name;         // as the front ends spell it: `napkin query NAME`
  std::string description;  // what its rows are, one line for the help
  // The rows it lists are those of this kind: the kind itself, or for `limits`
  // the rows of `criteria`, each then checked against a limit set by the
  // application (app::LimitsTable). Its fields and sources are that kind's.
  QueryKind rows_of;
  // The kind needs a limit set (the command line's --limits, the service's
  // `limits` parameter, Python's limits=); no other kind takes one.
  bool takes_limits = false;
  // Its key in the test summary of the service (GET /api/v1/tests/ID), under its name.
  TestSummaryPart test_summary = TestSummaryPart::kNone;

  // How the rows are read (db/catalogue_query.cpp), for a kind that is its own rows_of.
  // Its columns after test_id, series and variant, in order; then the summary fields of
  // `summary_groups` (engine::SummaryFieldsOf); then `salvaged` when `salvaged`.
  std::vector<QueryField> own_fields{};
  std::vector<engine::SummaryGroup> summary_groups{};
  bool salvaged = false;
  // What the rows are selected from, for each test's latest result (a view), and for
  // the results of one config, where "?CONFIG" stands for that config's key. Both
  // empty: the SELECT of the summary kinds, generated from engine::SummaryFields()
  // (a new criterion's column needs no view; docs/developing.md "Adding a criterion").
  std::string latest_source{};
  std::string config_source{};
  // The columns after test_id that order the rows of one test (", a, b"; empty: none).
  std::string tie_order{};
};

// Every query kind, in the order the front ends list them.
const std::vector<QueryKindSpec>& QueryKinds();

// The row of `kind`.
const QueryKindSpec& QueryKindOf(QueryKind kind);

// The row named `name`; nullptr when there is none.
const QueryKindSpec* FindQueryKind(std::string_view name);

// The names of QueryKinds(), in order.
std::vector<std::string> QueryKindNames();

// The one sentence every front end refuses an unknown kind with: "the query
// kind must be tests, hic, ... or limits; it is 'x'." (`name` quoted with its
// control characters escaped).
std::string UnknownQueryKindSentence(std::string_view name);

// The row named `name`; throws UsageError(UnknownQueryKindSentence(name)) when there is none.
const QueryKindSpec& ParseQueryKind(std::string_view name);

}  // namespace napkin::db
