#pragma once
// The row selection of a query (docs/formats.md "Query filters"), as
// `napkin query` takes it (--series, --variant: repeatable, any of the
// names; --where: repeatable, all must hold; --sort, --limit and --config)
// and napkin.Catalogue.query: text turned into a db::QueryRequest.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "app/limits.h"
#include "app/request_options.h"
#include "db/catalogue.h"

namespace napkin::app {

struct QueryFilterOptions {
  db::TestFilter tests;  // --series, --variant (repeatable: any of the names), as every command selects tests
  std::vector<std::string> where;
  std::vector<std::string> sort;
  std::string limit;   // text, so that a bad value is napkin's one-line usage error
  std::string config;  // NAME or HASH-PREFIX; empty: each test's latest result
  // Who asked: errors name the options as it spells them ("--sort", "parameter 'sort'").
  FrontEnd front_end = FrontEnd::kCommandLine;

  // The request for query `kind` without its config (needs no catalogue, so
  // a malformed option is reported first); throws UsageError (one line) for
  // a bad where, sort or limit, naming the option as `front_end` spells it.
  db::QueryRequest Request(db::QueryKind kind) const;
};

// A query as `napkin query KIND` and napkin.Catalogue.query ask it.
struct Query {
  std::string kind;  // a name of db::QueryKinds()
  QueryFilterOptions filters;
  std::optional<std::string>
      limits;  // a kind that takes_limits: a limits preset name or JSON file (LoadLimits)
};

// A query checked without a catalogue, so that a malformed one is reported
// before a catalogue is opened.
struct PreparedQuery {
  db::QueryKind kind;        // as asked (db::QueryKindSpec::rows_of says whose rows it reads)
  db::QueryRequest request;  // without its config
  std::string config;        // QueryFilterOptions::config
  std::optional<LimitSet> limits;
};

// Throws UsageError for an unknown kind (db::UnknownQueryKindSentence, the
// sentence of every front end), a kind that takes limits without `limits` or
// `limits` with another kind, and QueryFilterOptions::Request's errors;
// LoadLimits' errors.
PreparedQuery PrepareQuery(const Query& query);

// The query's rows: db::Catalogue::Query under the query's config (Stored,
// app/result_selection.h; each test's latest result without one), for a
// kind that takes limits checked against them (LimitsTable).
db::Table RunQuery(db::Catalogue& catalogue, const PreparedQuery& query);

// `--sort FIELD[:asc|:desc]` against `fields`; throws UsageError.
db::SortKey ParseSortKey(std::string_view text, const std::vector<db::QueryField>& fields,
                         FrontEnd front_end = FrontEnd::kCommandLine);

// `--limit N`: a whole number >= 0; throws UsageError.
std::int64_t ParseRowLimit(std::string_view text, FrontEnd front_end = FrontEnd::kCommandLine);

}  // namespace napkin::app
