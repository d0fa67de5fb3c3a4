#include "app/query.h"

#include <algorithm>
#include <charconv>
#include <system_error>

#include "app/result_selection.h"
#include "app/where_parser.h"
#include "common/error.h"
#include "common/joined.h"
#include "util/text.h"

namespace napkin::app {

db::QueryRequest QueryFilterOptions::Request(db::QueryKind kind) const {
  const std::vector<db::QueryField> fields = db::QueryFields(kind);
  db::QueryRequest request;
  request.tests = tests;
  for (const std::string& expression : where)
    request.where.push_back(ParseWhereExpression(expression, fields, front_end));
  for (const std::string& key : sort) request.sort.push_back(ParseSortKey(key, fields, front_end));
  if (!limit.empty()) request.limit = ParseRowLimit(limit, front_end);
  return request;
}

PreparedQuery PrepareQuery(const Query& query) {
  const db::QueryKindSpec& kind = db::ParseQueryKind(query.kind);
  if (kind.takes_limits && !query.limits)
    throw UsageError("`napkin query " + kind.name + "` needs " +
                     (query.filters.front_end == FrontEnd::kCommandLine
                          ? "--limits NAME"
                          : OptionName(query.filters.front_end, "limits")) +
                     " (presets: " + Joined(LimitPresets()) + ").");
  if (!kind.takes_limits && query.limits) {
    std::vector<std::string> taking;
    for (const db::QueryKindSpec& other : db::QueryKinds())
      if (other.takes_limits) taking.push_back("`napkin query " + other.name + "`");
    throw UsageError(OptionName(query.filters.front_end, "limits") + " applies to " + JoinedChoices(taking) +
                     " only.");
  }
  PreparedQuery prepared{kind.kind, {}, query.filters.config, std::nullopt};
  if (kind.takes_limits) prepared.limits = LoadLimits(*query.limits);
  prepared.request = query.filters.Request(kind.kind);
  return prepared;
}

db::Table RunQuery(db::Catalogue& catalogue, const PreparedQuery& query) {
  db::QueryRequest request = query.request;
  if (!query.config.empty()) request.config = ResolveConfigSelector(catalogue, query.config).id;
  const db::Table table = catalogue.Query(query.kind, request);
  return query.limits ? LimitsTable(table, *query.limits) : table;
}

db::SortKey ParseSortKey(std::string_view text, const std::vector<db::QueryField>& fields,
                         FrontEnd front_end) {
  const std::size_t colon = text.rfind(':');
  db::SortKey key{std::string(text.substr(0, colon)), false};
  if (colon != std::string_view::npos) {
    const std::string direction = util::ToLower(text.substr(colon + 1));
    if (direction != "asc" && direction != "desc")
      throw UsageError(OptionName(front_end, "sort") + " \"" + util::Abbreviated(text) +
                       "\": the direction after ':' is asc or desc, not '" +
                       util::Abbreviated(text.substr(colon + 1)) + "'.");
    key.descending = direction == "desc";
  }
  if (std::none_of(fields.begin(), fields.end(),
                   [&](const db::QueryField& f) { return f.name == key.field; }))
    throw UsageError(OptionName(front_end, "sort") + " \"" + util::Abbreviated(text) + "\": unknown field '" +
                     util::Abbreviated(key.field) + "'; the fields are " + db::FieldNames(fields) + ".");
  return key;
}

std::int64_t ParseRowLimit(std::string_view text, FrontEnd front_end) {
  std::int64_t limit = -1;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), limit);
  if (error != std::errc() || end != text.data() + text.size() || limit < 0)
    throw UsageError(OptionName(front_end, "limit") + " takes a whole number of rows, 0 or more, not '" +
                     util::Abbreviated(text) + "'.");
  return limit;
}

}  // namespace napkin::app
