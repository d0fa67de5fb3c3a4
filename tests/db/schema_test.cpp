// The schema agrees with the one summary-field table (engine/summary_fields.h):
// the results table's summary columns are the table's names, in its order, and
// the summary views' columns those of schema 13. The schema files are not generated from the
// table (catalogues on disk keep their columns), so this test is what binds them.
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "db/catalogue.h"
#include "db/sqlite.h"
#include "engine/summary_fields.h"
#include "tests/support/test_support.h"

namespace napkin::db {
namespace {

using engine::SummaryGroup;

// Column names of a table or view, in order.
std::vector<std::string> Columns(Connection& connection, const std::string& table) {
  auto info = connection.Prepare("SELECT name FROM pragma_table_info(?1) ORDER BY cid");
  info->Bind(1, table);
  std::vector<std::string> columns;
  while (info->Step()) columns.push_back(info->ColumnText(0));
  return columns;
}

std::vector<std::string> Concatenated(std::vector<std::string> head,
                                      std::initializer_list<std::vector<std::string>> tails) {
  for (const std::vector<std::string>& tail : tails) head.insert(head.end(), tail.begin(), tail.end());
  return head;
}

class SchemaTest : public ::testing::Test {
 protected:
  void SetUp() override {
    Catalogue::Open(path_);  // creates the catalogue at the newest schema version
    connection_.emplace(Connection::Open(path_, {.read_only = true}));
  }

  napkin::test_support::TempDir dir_;
  std::string path_ = dir_ / "catalogue.db";
  std::optional<Connection> connection_;
};

TEST_F(SchemaTest, ResultsColumnsAreTheSummaryFieldsInOrder) {
  // napkin_version (schema/007_provenance.sql) was appended after the summary
  // fields of schemas 1-3 (the last of them hic_d), every later field after it.
  std::vector<std::string> before, after, risks;
  for (const engine::SummaryField& field : engine::SummaryFields()) {
    (after.empty() && (before.empty() || before.back() != "hic_d") ? before : after).emplace_back(field.name);
    if (field.group == SummaryGroup::kRisk) risks.emplace_back(field.name);
  }
  ASSERT_EQ(before.back(), "hic_d");
  EXPECT_EQ(Columns(*connection_, "results"),
            Concatenated({"id", "test_id", "config_id", "solver", "computed_at"},
                         {before, {"napkin_version"}, after}));
  EXPECT_EQ(risks, (std::vector<std::string>{"hic15_p_ais3", "hic36_p_ais4", "bric_p_ais3", "bric_p_ais4"}));
}

TEST_F(SchemaTest, SummaryViewsShowTheFieldsOfTheirGroupUpToSchema13) {
  // The views of the summary groups are for plain sqlite3 and are no longer
  // redefined per criterion: they show their group's fields up to schema 13;
  // the fields appended after bric_p_ais4, schema 8's last (ubric, schema 15,
  // ...), are in v_latest_results and in `napkin query`, whose SELECT is
  // generated from the table (db/catalogue_query.cpp).
  const engine::SummaryField* last_of_schema_13 = engine::FindSummaryField("bric_p_ais4");
  const auto through_schema_13 = [last_of_schema_13](SummaryGroup group) {
    std::vector<std::string> names;
    for (const engine::SummaryField* field : engine::SummaryFieldsOf({group}))
      if (field <= last_of_schema_13) names.emplace_back(field->name);  // fields of one array, in table order
    return names;
  };
  const std::vector<std::string> labels = {"test_id", "series", "variant"};
  const std::vector<std::string> hic = through_schema_13(SummaryGroup::kHic);
  const std::vector<std::string> rotation = through_schema_13(SummaryGroup::kRotation);
  EXPECT_EQ(Columns(*connection_, "v_hic"), Concatenated(labels, {hic}));
  EXPECT_EQ(Columns(*connection_, "v_rotation"), Concatenated(labels, {rotation}));
  EXPECT_EQ(Columns(*connection_, "v_criteria"), Concatenated(labels, {hic, rotation, {"salvaged"}}));
  EXPECT_EQ(Columns(*connection_, "v_risk"), Concatenated(labels, {through_schema_13(SummaryGroup::kRisk)}));
  EXPECT_EQ(Columns(*connection_, "v_latest_results"), Columns(*connection_, "results"));
}

}  // namespace
}  // namespace napkin::db
