// Tables as every front end prints them (app/table_output.h): CSV quoting,
// JSON types and nulls, the aligned table, non-finite numbers, and stored text
// escaped (docs/formats.md "Names, limits and escaping").
#include "app/table_output.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>

#include "common/error.h"
#include "util/text.h"

namespace napkin::app {
namespace {

// Whether `text` holds a control character other than its line ends.
bool HasRawControlCharacter(const std::string& text) {
  for (const char c : text)
    if (c != '\n' && util::HasControlCharacter(std::string_view(&c, 1))) return true;
  return false;
}

TEST(TableOutput, NullsQuotingAndNonFiniteNumbers) {
  db::Table table;
  table.columns = {"name", "count", "value"};
  table.rows.push_back({std::string("a, \"b\""), std::int64_t{3}, 0.1});
  table.rows.push_back({std::monostate{}, std::int64_t{-12}, std::numeric_limits<double>::quiet_NaN()});
  table.rows.push_back({std::string("plain"), std::monostate{}, 1e-300});

  EXPECT_EQ(FormatTable(table, TableFormat::kCsv),
            "name,count,value\n"
            "\"a, \"\"b\"\"\",3,0.1\n"
            ",-12,\n"
            "plain,,1e-300\n");
  const nlohmann::ordered_json json = nlohmann::ordered_json::parse(FormatTable(table, TableFormat::kJson));
  ASSERT_EQ(json.size(), 3u);
  EXPECT_EQ(json[0]["name"], "a, \"b\"");
  EXPECT_TRUE(json[0]["count"].is_number_integer());
  EXPECT_EQ(json[0]["value"].get<double>(), 0.1);
  EXPECT_TRUE(json[1]["name"].is_null());
  EXPECT_TRUE(json[1]["value"].is_null());
  EXPECT_EQ(json[2]["value"].get<double>(), 1e-300);
  EXPECT_EQ(FormatTable(table, TableFormat::kTable),
            "name    count   value\n"
            "------  -----  ------\n"
            "a, \"b\"      3     0.1\n"
            "-         -12     nan\n"
            "plain       -  1e-300\n");
  EXPECT_EQ(FormatTable(db::Table{{"x"}, {}}, TableFormat::kTable), "x\n-\n(no rows)\n");
  EXPECT_THROW(ParseTableFormat("xml"), InputError);
}

// Stored text reaches a table escaped (util::EscapeControl): no terminal escape sequence, no line
// break of its own.
TEST(TableOutput, StoredTextIsEscaped) {
  const db::Table table{{"test_id", "hic15"}, {{std::string("a\x1b[2Jb\nc"), 1.5}}};
  EXPECT_EQ(FormatTable(table, TableFormat::kCsv), "test_id,hic15\na\\x1b[2Jb\\nc,1.5\n");
  const std::string human = FormatTable(table, TableFormat::kTable);
  EXPECT_FALSE(HasRawControlCharacter(human)) << human;
  EXPECT_NE(human.find("a\\x1b[2Jb\\nc"), std::string::npos) << human;
}

}  // namespace
}  // namespace napkin::app
