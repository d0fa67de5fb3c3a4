// Catalogue: `napkin query` tables (docs/formats.md "Per-test summary fields"
// and "Query filters") from the views of schema/002_query_views.sql (for the
// kinds of results, the same rows read test by test: LatestResultsSql), or,
// for one processing config, from the same joins over that config's results.
// Field names reach the SQL only after they were found in QueryFields(kind);
// every value is bound as a parameter.
#include <algorithm>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "common/error.h"
#include "common/joined.h"
#include "db/catalogue.h"
#include "db/catalogue_internal.h"
#include "engine/summary_fields.h"

namespace napkin::db {
namespace {

// The row whose columns and sources `kind` reads: its own, or (limits) that of the kind it checks.
const QueryKindSpec& RowsOf(QueryKind kind) { return QueryKindOf(QueryKindOf(kind).rows_of); }

// A column name as an SQL identifier (names come from QueryFields; quoting
// also covers the keyword "check").
std::string Identifier(const std::string& name) {
  std::string quoted = "\"";
  for (const char c : name) {
    quoted += c;
    if (c == '"') quoted += '"';
  }
  return quoted + "\"";
}

// The statement's parameter values, numbered ?1, ?2, ... in the order added.
class Parameters {
 public:
  using Value = std::variant<std::int64_t, double, std::string>;
  std::string Add(Value value) {
    values_.push_back(std::move(value));
    // Appended, not `"?" + temporary` (GCC 12's false -Wrestrict, util/text.h InQuotes).
    std::string placeholder = "?";
    placeholder += std::to_string(values_.size());
    return placeholder;
  }
  void BindTo(Statement& statement) const {
    for (std::size_t i = 0; i < values_.size(); ++i)
      std::visit([&](const auto& value) { statement.Bind(static_cast<int>(i + 1), value); }, values_[i]);
  }

 private:
  std::vector<Value> values_;
};

const QueryField& FindField(QueryKind kind, const std::vector<QueryField>& fields, const std::string& name,
                            const char* option) {
  const auto found =
      std::find_if(fields.begin(), fields.end(), [&](const QueryField& field) { return field.name == name; });
  if (found == fields.end())
    throw UsageError(std::string(option) + " names unknown field '" + name + "'; the fields of query " +
                     QueryKindOf(kind).name + " are " + FieldNames(fields) + ".");
  return *found;
}

std::string ComparisonSql(QueryKind kind, const std::vector<QueryField>& fields,
                          const WhereComparison& comparison, Parameters& parameters) {
  const QueryField& field = FindField(kind, fields, comparison.field, "--where");
  if (field.numeric != std::holds_alternative<double>(comparison.value))
    throw UsageError("--where compares " + std::string(field.numeric ? "numeric" : "text") + " field '" +
                     field.name + "' with " + (field.numeric ? "text" : "a number") + "; compare it with " +
                     (field.numeric ? "a number." : "text."));
  const std::string value = std::visit([&](const auto& v) { return parameters.Add(v); }, comparison.value);
  return Identifier(field.name) + " " + ComparisonOperatorText(comparison.op) + " " + value;
}

// The SQL of `expression`, written for SQLite's parser, whose stack (100
// entries in 3.40) holds an entry for every parenthesis still open: one
// opened first costs one entry, one opened after `x AND` three. So each
// junction writes its most nested operand first (`and` and `or` give the
// same answer in any order, NULLs included), and only an `or` inside an
// `and` is put in parentheses (SQL's AND binds tighter than OR, as --where's
// `and` does): `a and (b or (c and d))` is written `(c AND d OR b) AND a`.
// With kMaxWhereNesting and kMaxWhereComparisons this keeps every accepted
// filter parseable (tests/cli/where_limits_test.cpp).
std::string WhereSql(QueryKind kind, const std::vector<QueryField>& fields, const WhereExpression& expression,
                     Parameters& parameters) {
  if (const auto* comparison = std::get_if<WhereComparison>(&expression.node))
    return ComparisonSql(kind, fields, *comparison, parameters);
  const auto& junction = std::get<WhereJunction>(expression.node);
  if (junction.operands.empty()) throw std::invalid_argument("WhereJunction without operands");
  const bool is_and = junction.kind == WhereJunction::Kind::kAnd;
  const auto parenthesized = [&](const WhereExpression& operand) {
    const auto* inner = std::get_if<WhereJunction>(&operand.node);
    return is_and && inner != nullptr && inner->kind == WhereJunction::Kind::kOr;
  };
  std::vector<std::pair<int, const WhereExpression*>> operands;  // (nesting, operand)
  for (const WhereExpression& operand : junction.operands)
    operands.emplace_back(WhereOrNesting(operand) + (parenthesized(operand) ? 1 : 0), &operand);
  std::stable_sort(operands.begin(), operands.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  std::string sql;
  for (const auto& [nesting, operand] : operands) {
    if (!sql.empty()) sql += is_and ? " AND " : " OR ";
    const std::string operand_sql = WhereSql(kind, fields, *operand, parameters);
    sql += parenthesized(*operand) ? "(" + operand_sql + ")" : operand_sql;
  }
  return sql;
}

// Throws UsageError when the --where expressions of one query exceed the
// limits of db/where_expression.h (the parser keeps each expression within them).
void CheckWhereLimits(const std::vector<WhereExpression>& where) {
  std::size_t comparisons = 0;
  for (const WhereExpression& expression : where) {
    if (WhereOrNesting(expression) > kMaxWhereNesting)
      throw UsageError("a --where expression nests 'or' inside 'and' deeper than " +
                       std::to_string(kMaxWhereNesting) + " levels; write it with fewer parentheses.");
    comparisons += CountWhereComparisons(expression);
  }
  if (comparisons > kMaxWhereComparisons)
    throw UsageError("the --where expressions hold " + std::to_string(comparisons) +
                     " comparisons together; a query takes at most " + std::to_string(kMaxWhereComparisons) +
                     ".");
}

// Rows of results with the labels of their tests and every summary column
// (engine::SummaryFields()), from `results_of_tests` (FROM and WHERE naming
// results r and tests t): the one SELECT of the query kinds that show summary
// fields, with or without --config, generated from the table, so a new
// criterion's column needs no view (docs/developing.md "Adding a criterion";
// the v_hic, v_rotation, v_criteria and v_risk views are for plain sqlite3 and
// show the fields of schema version 13).
std::string LabelledResultsSql(const std::string& results_of_tests) {
  return "(SELECT t.external_id AS test_id, s.name AS series, t.variant AS variant, " +
         internal::SummaryColumnList("r.") +
         ", EXISTS (SELECT 1 FROM result_salvage AS rs WHERE rs.test_id = r.test_id AND rs.config_id = "
         "r.config_id) AS salvaged FROM " +
         results_of_tests + ")";
}

// The results of one config: the joins of the views.
std::string ResultsOfConfigSql(const std::string& config_parameter) {
  return LabelledResultsSql(
      "results AS r JOIN tests AS t ON t.id = r.test_id LEFT JOIN series AS s ON s.id = t.series_id "
      "WHERE r.config_id = " +
      config_parameter);
}

// Each test's latest result (that of the largest key, as v_latest_results
// has it): the rows of the views, found from the tests, so that SQLite reads
// the tests in test id order (their index) and a query in that order with
// --limit stops after its rows. The views start from the results and sort
// them all (docs/architecture.md "Catalogues of a million tests").
std::string LatestResultsSql() {
  return LabelledResultsSql(
      "tests AS t JOIN results AS r ON r.id = (SELECT max(latest.id) FROM results AS latest WHERE "
      "latest.test_id = t.id) LEFT JOIN series AS s ON s.id = t.series_id");
}

// What the rows of `kind` are selected from: its row's source (QueryKindSpec), or the
// SELECT of the summary kinds, each test's latest result or the results of `config`.
std::string SourceSql(QueryKind kind, const std::optional<ConfigId>& config, Parameters& parameters) {
  const QueryKindSpec& rows = RowsOf(kind);
  const bool generated = rows.latest_source.empty();
  if (!config) return generated ? LatestResultsSql() : rows.latest_source;
  const std::string config_parameter = parameters.Add(static_cast<std::int64_t>(*config));
  if (generated) return ResultsOfConfigSql(config_parameter);
  std::string sql = rows.config_source;
  constexpr std::string_view kConfig = "?CONFIG";
  const std::size_t at = sql.find(kConfig);
  if (at == std::string::npos || sql.find(kConfig, at + 1) != std::string::npos)
    throw std::logic_error("the config source of query " + rows.name + " names ?CONFIG other than once");
  return sql.replace(at, kConfig.size(), config_parameter);
}

// `column IN (names)` as a JSON array parameter; empty when `names` is empty.
std::string AnyOfSql(const char* column, const std::vector<std::string>& names, Parameters& parameters) {
  const std::optional<std::string> json = internal::JsonStringArray(names);
  if (!json) return "";
  return std::string(" AND ") + column + " IN (SELECT value FROM json_each(" + parameters.Add(*json) + "))";
}

Cell ReadCell(const Statement& row, int column) {
  switch (row.ColumnType(column)) {
    case SQLITE_INTEGER:
      return row.ColumnInt64(column);
    case SQLITE_FLOAT:
      return row.ColumnDouble(column);
    case SQLITE_TEXT:
      return row.ColumnText(column);
    case SQLITE_NULL:
      return std::monostate{};
    default:
      throw std::logic_error("query views hold no BLOB columns");
  }
}

}  // namespace

std::vector<QueryField> QueryFields(QueryKind kind) {
  const QueryKindSpec& rows = RowsOf(kind);
  std::vector<QueryField> fields = {{"test_id", false}, {"series", false}, {"variant", false}};
  fields.insert(fields.end(), rows.own_fields.begin(), rows.own_fields.end());
  for (const engine::SummaryGroup group : rows.summary_groups)
    for (const engine::SummaryField* field : engine::SummaryFieldsOf({group}))
      fields.push_back({field->name, true});
  // 1 when the result comes from salvaged channels (schema/012_salvage.sql).
  if (rows.salvaged) fields.push_back({"salvaged", true});
  return fields;
}

std::string FieldNames(const std::vector<QueryField>& fields) { return Joined(fields, &QueryField::name); }

Table Catalogue::Query(QueryKind kind, const TestFilter& filter) {
  QueryRequest request;
  request.tests = filter;
  return Query(kind, request);
}

Table Catalogue::Query(QueryKind kind, const QueryRequest& request) {
  const std::vector<QueryField> fields = QueryFields(kind);
  Parameters parameters;
  std::string sql = "SELECT ";
  for (std::size_t i = 0; i < fields.size(); ++i) sql += (i > 0 ? ", " : "") + Identifier(fields[i].name);
  sql += " FROM " + SourceSql(kind, request.config, parameters) + " WHERE 1";
  sql += AnyOfSql("series", request.tests.series, parameters);
  sql += AnyOfSql("variant", request.tests.variants, parameters);
  sql += AnyOfSql("test_id", request.tests.external_ids, parameters);
  CheckWhereLimits(request.where);
  for (const WhereExpression& expression : request.where)
    sql += " AND (" + WhereSql(kind, fields, expression, parameters) + ")";

  sql += " ORDER BY ";
  for (const SortKey& key : request.sort)
    sql += Identifier(FindField(kind, fields, key.field, "--sort").name) +
           (key.descending ? " DESC" : " ASC") + " NULLS LAST, ";
  sql += "test_id" + RowsOf(kind).tie_order;
  if (request.limit) {
    if (*request.limit < 0)
      throw UsageError("--limit must be a whole number of rows, 0 or more; it is " +
                       std::to_string(*request.limit) + ".");
    sql += " LIMIT " + parameters.Add(*request.limit);
  }

  auto select = connection_.Prepare(sql);
  parameters.BindTo(*select);
  Table table;
  for (int c = 0; c < select->ColumnCount(); ++c) table.columns.push_back(select->ColumnName(c));
  while (select->Step()) {
    std::vector<Cell>& row = table.rows.emplace_back();
    row.reserve(table.columns.size());
    for (int c = 0; c < select->ColumnCount(); ++c) row.push_back(ReadCell(*select, c));
  }
  return table;
}

}  // namespace napkin::db
