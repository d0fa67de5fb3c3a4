#include "db/where_expression.h"

#include <algorithm>
#include <charconv>
#include <system_error>

namespace napkin::db {
namespace {

std::string ShortestNumber(double value) {
  char buffer[64];
  const auto [end, error] = std::to_chars(buffer, buffer + sizeof buffer, value);
  return error == std::errc() ? std::string(buffer, end) : std::string("?");
}

std::string QuotedText(const std::string& text) {
  std::string quoted = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') quoted += '\\';
    quoted += c;
  }
  return quoted + "\"";
}

}  // namespace

const char* ComparisonOperatorText(ComparisonOperator op) {
  switch (op) {
    case ComparisonOperator::kEqual:
      return "=";
    case ComparisonOperator::kNotEqual:
      return "!=";
    case ComparisonOperator::kLess:
      return "<";
    case ComparisonOperator::kLessEqual:
      return "<=";
    case ComparisonOperator::kGreater:
      return ">";
    case ComparisonOperator::kGreaterEqual:
      return ">=";
  }
  return "?";
}

std::size_t CountWhereComparisons(const WhereExpression& expression) {
  const auto* junction = std::get_if<WhereJunction>(&expression.node);
  if (junction == nullptr) return 1;
  std::size_t count = 0;
  for (const WhereExpression& operand : junction->operands) count += CountWhereComparisons(operand);
  return count;
}

int WhereOrNesting(const WhereExpression& expression) {
  const auto* junction = std::get_if<WhereJunction>(&expression.node);
  if (junction == nullptr) return 0;
  int deepest = 0;
  for (const WhereExpression& operand : junction->operands) {
    const auto* inner = std::get_if<WhereJunction>(&operand.node);
    const bool parenthesized = junction->kind == WhereJunction::Kind::kAnd && inner != nullptr &&
                               inner->kind == WhereJunction::Kind::kOr;
    deepest = std::max(deepest, WhereOrNesting(operand) + (parenthesized ? 1 : 0));
  }
  return deepest;
}

std::string DescribeWhereExpression(const WhereExpression& expression) {
  if (const auto* comparison = std::get_if<WhereComparison>(&expression.node)) {
    const std::string value = std::holds_alternative<double>(comparison->value)
                                  ? ShortestNumber(std::get<double>(comparison->value))
                                  : QuotedText(std::get<std::string>(comparison->value));
    return comparison->field + " " + ComparisonOperatorText(comparison->op) + " " + value;
  }
  const auto& junction = std::get<WhereJunction>(expression.node);
  const char* keyword = junction.kind == WhereJunction::Kind::kAnd ? " and " : " or ";
  std::string text = "(";
  for (std::size_t i = 0; i < junction.operands.size(); ++i) {
    if (i > 0) text += keyword;
    text += DescribeWhereExpression(junction.operands[i]);
  }
  return text + ")";
}

}  // namespace napkin::db
