#pragma once
// The filter of `napkin query --where` as a tree (docs/formats.md "Query
// filters"): comparisons of one query field with one value, joined by `and`
// and `or`. No SQL here: cli::ParseWhereExpression builds it from text,
// Catalogue::Query turns it into SQL with every value bound as a parameter.
#include <string>
#include <variant>
#include <vector>

namespace napkin::db {

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

// The expression with every junction in parentheses and text values in
// double quotes, e.g. `(hic15 > 700 or (variant = "foam-a" and series = "sled"))`:
// shows how an expression was grouped (messages, tests).
std::string DescribeWhereExpression(const WhereExpression& expression);

}  // namespace napkin::db
