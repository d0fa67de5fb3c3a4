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

#include "db/catalogue.h"

namespace napkin::app {

struct QueryFilterOptions {
  std::vector<std::string> series;
  std::vector<std::string> variants;
  std::vector<std::string> where;
  std::vector<std::string> sort;
  std::string limit;   // text, so that a bad value is napkin's one-line usage error
  std::string config;  // NAME or HASH-PREFIX; empty: each test's latest result

  // The request for query `kind` without its config (needs no catalogue, so
  // a malformed option is reported first); throws UsageError (one line) for
  // a bad --where, --sort or --limit.
  db::QueryRequest Request(db::QueryKind kind) const;
  // The --config's key (ResolveConfigSelector), or none without --config.
  std::optional<db::ConfigId> Config(db::Catalogue& catalogue) const;
};

// `--sort FIELD[:asc|:desc]` against `fields`; throws UsageError.
db::SortKey ParseSortKey(std::string_view text, const std::vector<db::QueryField>& fields);

// `--limit N`: a whole number >= 0; throws UsageError.
std::int64_t ParseRowLimit(std::string_view text);

}  // namespace napkin::app
