// The --where parser (app/where_parser.h, docs/formats.md "Query
// filters"): precedence, parentheses, quoting, value types, and every error
// with its one-line message.
#include "app/where_parser.h"

#include <gtest/gtest.h>

#include "common/error.h"

namespace napkin::app {
namespace {

const std::vector<db::QueryField>& HicFields() {
  static const std::vector<db::QueryField> kFields = db::QueryFields(db::QueryKind::kHic);
  return kFields;
}

std::string FieldList() {
  std::string list;
  for (const db::QueryField& field : HicFields()) list += (list.empty() ? "" : ", ") + field.name;
  return list;
}

std::string Grouping(const std::string& text) {
  return db::DescribeWhereExpression(ParseWhereExpression(text, HicFields()));
}

// The UsageError's message for `text` ("" when it parses).
std::string ErrorOf(const std::string& text) {
  try {
    ParseWhereExpression(text, HicFields());
  } catch (const UsageError& error) {
    return error.what();
  }
  return "";
}

// The message a malformed `text` gets: the expression, the problem, the fields.
std::string Expected(const std::string& text, const std::string& problem) {
  return "--where \"" + text + "\": " + problem + "; the fields are " + FieldList() + ".";
}

TEST(WhereExpression, AndBindsTighterThanOr) {
  EXPECT_EQ(Grouping("hic15>700 or variant=foam-a and series=sled"),
            R"((hic15 > 700 or (variant = "foam-a" and series = "sled")))");
  EXPECT_EQ(Grouping("hic15>700 and variant=foam-a or series=sled"),
            R"(((hic15 > 700 and variant = "foam-a") or series = "sled"))");
  EXPECT_EQ(Grouping("hic15 < 1 or hic15 > 2 or hic36 = 3"), "(hic15 < 1 or hic15 > 2 or hic36 = 3)");
  EXPECT_EQ(Grouping("hic15 < 1 and hic15 > 2 and hic36 = 3 or a3ms_g >= 4 and a3ms_g <= 5"),
            "((hic15 < 1 and hic15 > 2 and hic36 = 3) or (a3ms_g >= 4 and a3ms_g <= 5))");
}

TEST(WhereExpression, ParenthesesGroupFirst) {
  EXPECT_EQ(Grouping("(hic15>700 or variant=foam-a) and series=sled"),
            R"(((hic15 > 700 or variant = "foam-a") and series = "sled"))");
  EXPECT_EQ(Grouping("hic15>700 and (variant=foam-a or (series=sled and hic36<1))"),
            R"((hic15 > 700 and (variant = "foam-a" or (series = "sled" and hic36 < 1))))");
  EXPECT_EQ(Grouping("((hic15 != 1))"), "hic15 != 1");
}

TEST(WhereExpression, KeywordsAreCaseInsensitiveAndOperatorsNeedNoBlanks) {
  EXPECT_EQ(Grouping("hic15>=1 AND hic36<=2 Or test_id!=t1"),
            R"(((hic15 >= 1 and hic36 <= 2) or test_id != "t1"))");
  const db::WhereExpression expression = ParseWhereExpression("hic15<1", HicFields());
  const auto& comparison = std::get<db::WhereComparison>(expression.node);
  EXPECT_EQ(comparison.field, "hic15");
  EXPECT_EQ(comparison.op, db::ComparisonOperator::kLess);
  EXPECT_EQ(std::get<double>(comparison.value), 1.0);
  for (const auto& [text, op] : std::vector<std::pair<std::string, db::ComparisonOperator>>{
           {"=", db::ComparisonOperator::kEqual},
           {"!=", db::ComparisonOperator::kNotEqual},
           {"<", db::ComparisonOperator::kLess},
           {"<=", db::ComparisonOperator::kLessEqual},
           {">", db::ComparisonOperator::kGreater},
           {">=", db::ComparisonOperator::kGreaterEqual}}) {
    const db::WhereExpression parsed = ParseWhereExpression("a3ms_g" + text + "80", HicFields());
    EXPECT_EQ(std::get<db::WhereComparison>(parsed.node).op, op) << text;
  }
}

TEST(WhereExpression, ValuesAreNumbersForNumericFieldsAndTextForTextFields) {
  auto value = [](const std::string& text) {
    return std::get<db::WhereComparison>(ParseWhereExpression(text, HicFields()).node).value;
  };
  EXPECT_EQ(std::get<double>(value("hic15 > -1.5e2")), -150.0);
  EXPECT_EQ(std::get<double>(value("hic15 > +3")), 3.0);
  EXPECT_EQ(std::get<double>(value("hic15 > 0.1")), 0.1);
  EXPECT_EQ(std::get<std::string>(value("test_id = 0012")), "0012") << "text fields keep the text as typed";
  EXPECT_EQ(std::get<std::string>(value("variant = foam-a")), "foam-a");
  EXPECT_EQ(std::get<std::string>(value("variant = and")), "and")
      << "a keyword in a value's place is a value";
  EXPECT_EQ(std::get<std::string>(value("variant = Foam.B_2")), "Foam.B_2");
}

TEST(WhereExpression, QuotedStringsHoldBlanksQuotesParenthesesAndOperators) {
  auto text = [](const std::string& where) {
    return std::get<std::string>(
        std::get<db::WhereComparison>(ParseWhereExpression(where, HicFields()).node).value);
  };
  EXPECT_EQ(text(R"(series = "sled 2024 (A) <= x and y")"), "sled 2024 (A) <= x and y");
  EXPECT_EQ(text(R"(series = "say \"hi\"")"), R"(say "hi")");
  EXPECT_EQ(text(R"(series = "C:\\data\\")"), R"(C:\data\)");
  EXPECT_EQ(text(R"(series = "")"), "");
  EXPECT_EQ(text(R"(series="x'); DROP TABLE tests;--")"), "x'); DROP TABLE tests;--");
  EXPECT_EQ(Grouping(R"x(series="a or b" or variant="(c)")x"), R"x((series = "a or b" or variant = "(c)"))x");
}

TEST(WhereExpression, EmptyExpression) {
  EXPECT_EQ(ErrorOf(""), Expected("", "the expression is empty"));
  EXPECT_EQ(ErrorOf("  "), Expected("  ", "the expression is empty"));
}

TEST(WhereExpression, UnknownField) {
  EXPECT_EQ(ErrorOf("hic16>700"), Expected("hic16>700", "unknown field 'hic16' at column 1"));
  EXPECT_EQ(ErrorOf("hic15>1 and HIC36>1"),
            Expected("hic15>1 and HIC36>1", "unknown field 'HIC36' at column 13"));
  EXPECT_EQ(ErrorOf("bric>1"), Expected("bric>1", "unknown field 'bric' at column 1"))
      << "a rotation field is not a field of query hic";
}

TEST(WhereExpression, MissingFieldName) {
  EXPECT_EQ(ErrorOf(">700"), Expected(">700", "expected a field name at column 1, found '>'"));
  EXPECT_EQ(ErrorOf("hic15>1 and"),
            Expected("hic15>1 and", "expected a field name at column 12, found the end"));
  EXPECT_EQ(ErrorOf("and hic15>1"),
            Expected("and hic15>1", "expected a field name at column 1, found 'and'"));
  EXPECT_EQ(ErrorOf(R"("hic15">1)"),
            Expected(R"("hic15">1)", R"(expected a field name at column 1, found "hic15")"));
  EXPECT_EQ(ErrorOf("()"), Expected("()", "expected a field name at column 2, found ')'"));
}

TEST(WhereExpression, MissingOperator) {
  EXPECT_EQ(
      ErrorOf("hic15 700"),
      Expected("hic15 700", "expected an operator (= != < <= > >=) after 'hic15' at column 7, found '700'"));
  EXPECT_EQ(
      ErrorOf("hic15"),
      Expected("hic15", "expected an operator (= != < <= > >=) after 'hic15' at column 6, found the end"));
}

TEST(WhereExpression, MissingValue) {
  EXPECT_EQ(ErrorOf("hic15>"), Expected("hic15>", "expected a value after '>' at column 7, found the end"));
  EXPECT_EQ(ErrorOf("hic15>>700"),
            Expected("hic15>>700", "expected a value after '>' at column 7, found '>'"));
  EXPECT_EQ(ErrorOf("hic15==700"),
            Expected("hic15==700", "expected a value after '=' at column 7, found '='"));
  EXPECT_EQ(ErrorOf("hic15 = (1)"),
            Expected("hic15 = (1)", "expected a value after '=' at column 9, found '('"));
}

TEST(WhereExpression, TrailingTokens) {
  EXPECT_EQ(ErrorOf("hic15>1 hic36>2"),
            Expected("hic15>1 hic36>2",
                     "expected 'and', 'or' or the end of the expression at column 9, found 'hic36'"));
  EXPECT_EQ(ErrorOf("hic15>1)"),
            Expected("hic15>1)", "expected 'and', 'or' or the end of the expression at column 8, found ')'"));
  EXPECT_EQ(ErrorOf("(hic15>1 hic36>2)"),
            Expected("(hic15>1 hic36>2)", "expected 'and', 'or' or ')' at column 10, found 'hic36'"));
}

TEST(WhereExpression, UnclosedParenthesis) {
  EXPECT_EQ(ErrorOf("(hic15>1 or (hic36>2)"),
            Expected("(hic15>1 or (hic36>2)",
                     "the '(' at column 1 is never closed (the expression ends at column 22)"));
}

TEST(WhereExpression, BadQuotingAndStrayCharacters) {
  EXPECT_EQ(ErrorOf(R"(variant="foam)"),
            Expected(R"(variant="foam)", "the text value starting at column 9 has no closing '\"'"));
  EXPECT_EQ(
      ErrorOf(R"(variant="a\n")"),
      Expected(R"(variant="a\n")",
               R"(unknown escape at column 11 (inside double quotes, \" is a quote and \\ a backslash))"));
  EXPECT_EQ(ErrorOf("variant='foam-a'"),
            Expected("variant='foam-a'",
                     "single quote at column 9: write text values in double quotes (\"like this\")"));
  EXPECT_EQ(ErrorOf("hic15 ! 700"),
            Expected("hic15 ! 700", "'!' at column 7 is not an operator (not equal is !=)"));
}

TEST(WhereExpression, NumericFieldsTakeNumbersOnly) {
  EXPECT_EQ(ErrorOf("hic15>abc"),
            Expected("hic15>abc", "field 'hic15' holds numbers, but 'abc' at column 7 is not a number"));
  EXPECT_EQ(
      ErrorOf(R"(hic15>"700")"),
      Expected(R"(hic15>"700")", R"(field 'hic15' holds numbers, but "700" at column 7 is not a number)"));
  for (const char* word : {"inf", "nan", "1e999", "7OO", "+-1", "0x10", "1,5"})
    EXPECT_NE(ErrorOf(std::string("hic15>") + word).find("is not a number"), std::string::npos) << word;
}

TEST(WhereExpression, ErrorsAreOneLine) {
  const std::string message = ErrorOf("hic15>\nabc");
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_EQ(message,
            Expected("hic15> abc", "field 'hic15' holds numbers, but 'abc' at column 8 is not a number"));
}

}  // namespace
}  // namespace napkin::app
