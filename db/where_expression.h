#pragma once
// The filter of `napkin query --where` as a tree (docs/formats.md "Query
// filters"): comparisons of one query field with one value, joined by `and`
// and `or`. No SQL here: app::ParseWhereExpression builds it from text,
// Catalogue::Query turns it into SQL with every value bound as a parameter.
#include <cstddef>
#include <string>
#include <variant>
#include <vector>

namespace napkin::db {

// Limits of a filter, so that every filter napkin accepts also runs
// (docs/formats.md "Query filters"). SQLite 3.40 parses with a fixed stack of
// 100 entries (YYSTACKDEPTH; "parser stack overflow" about 27 right-nested
// parentheses deep) and refuses expression trees deeper than 1,000
// (SQLITE_MAX_EXPR_DEPTH; `a or b or ...` is a chain as deep as it is long).
// Catalogue::Query writes the SQL so that these limits stay well inside both
// (tests/cli/where_limits_test.cpp runs filters at the limits on every query).
//
// Parentheses inside parentheses, in the text of one expression.
inline constexpr int kMaxWhereNesting = 32;
// Comparisons in one expression, and over all the expressions of one query.
inline constexpr std::size_t kMaxWhereComparisons = 500;

enum class ComparisonOperator { kEqual, kNotEqual, kLess, kLessEqual, kGreater, kGreaterEqual };

// "=", "!=", "<", "<=", ">", ">=".
const char* ComparisonOperatorText(ComparisonOperator op);

// `field op value`: a number for a numeric field (compared numerically),
// text for a text field (compared byte by byte). A field that is NULL
// matches no comparison, `!=` included (SQL semantics).
struct WhereComparison {
  std::string field;
  ComparisonOperator op = ComparisonOperator::kEqual;
  std::variant<double, std::string> value;
};

struct WhereExpression;

// `and` (every operand holds) or `or` (at least one holds) over two or more operands.
struct WhereJunction {
  enum class Kind { kAnd, kOr };
  Kind kind = Kind::kAnd;
  std::vector<WhereExpression> operands;
};

struct WhereExpression {
  std::variant<WhereComparison, WhereJunction> node;
};

// The number of comparisons in `expression`.
std::size_t CountWhereComparisons(const WhereExpression& expression);

// How deep `or` junctions nest inside `and` junctions (the parentheses the
// SQL needs, as the text needed them: `a and (b or (c and (d or e)))` is 2).
int WhereOrNesting(const WhereExpression& expression);

// The expression with every junction in parentheses and text values in
// double quotes, e.g. `(hic15 > 700 or (variant = "foam-a" and series = "sled"))`:
// shows how an expression was grouped (messages, tests).
std::string DescribeWhereExpression(const WhereExpression& expression);

}  // namespace napkin::db
