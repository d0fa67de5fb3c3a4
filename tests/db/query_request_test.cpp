// Catalogue::Query with a QueryRequest (docs/formats.md "Query filters"):
// where trees over the views' columns with every value bound (SQL-like text
// is a value), NULL fields matching nothing, sorting with NULLs last and
// ties by test id, limits, the result set of one config, repeated series and
// variants, and the refusals.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>

#include "common/error.h"
#include "db/catalogue.h"
#include "engine/summary_fields.h"
#include "tests/db/db_test_helpers.h"
#include "tests/support/db/catalogue_inspector.h"

namespace napkin::db {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::IsEmpty;
using ::testing::ThrowsMessage;

WhereExpression Compare(std::string field, ComparisonOperator op, std::variant<double, std::string> value) {
  return WhereExpression{WhereComparison{std::move(field), op, std::move(value)}};
}

WhereExpression Junction(WhereJunction::Kind kind, std::vector<WhereExpression> operands) {
  return WhereExpression{WhereJunction{kind, std::move(operands)}};
}

// A summary whose every field is `base` plus the field's position, and the given HIC15.
engine::TestSummary Summary(double base, double hic15) {
  engine::TestSummary summary;
  double offset = 0.0;
  for (const engine::SummaryField& field : engine::SummaryFields()) field.Set(summary, base + offset++);
  summary.hic15.value = hic15;
  summary.findings = {
      {"bias", "cg_x", engine::Severity::kInfo, "Offset removed at " + std::to_string(base) + "."}};
  return summary;
}

class QueryRequestTest : public ::testing::Test {
 protected:
  void SetUp() override {
    array_ = catalogue_.WriteArray(test_support::IdealArray());
    config_ = catalogue_.WriteConfig(test_support::DefaultConfig());
    other_config_ = catalogue_.WriteConfig(test_support::DefaultConfig(R"({"filter":"cfc180"})"));
    // id    series  variant  hic15 (default config)
    // a1    sled    A        700
    // a2    sled    B        900
    // a3    tower   A        NULL (NaN)
    // a4    -       B        500
    // a5    sled    A        (no result)
    const TestId a1 = test_support::AddTest(catalogue_, array_, "a1", "sled", "A");
    const TestId a2 = test_support::AddTest(catalogue_, array_, "a2", "sled", "B");
    const TestId a3 = test_support::AddTest(catalogue_, array_, "a3", "tower", "A");
    const TestId a4 = test_support::AddTest(catalogue_, array_, "a4", std::nullopt, "B");
    test_support::AddTest(catalogue_, array_, "a5", "sled", "A");
    catalogue_.WriteResult(a1, config_, Summary(10, 700), "exact");
    catalogue_.WriteResult(a2, config_, Summary(20, 900), "exact");
    catalogue_.WriteResult(a3, config_, Summary(30, std::numeric_limits<double>::quiet_NaN()), "exact");
    catalogue_.WriteResult(a4, config_, Summary(40, 500), "exact");
    // a2 under the other config: its latest result, HIC15 650.
    catalogue_.WriteResult(a2, other_config_, Summary(50, 650), "exact");
  }

  // The test ids of the rows of `kind` under `request`.
  std::vector<std::string> Ids(const QueryRequest& request, QueryKind kind = QueryKind::kHic) {
    std::vector<std::string> ids;
    for (const auto& row : catalogue_.Query(kind, request).rows) ids.push_back(std::get<std::string>(row[0]));
    return ids;
  }
  QueryRequest Where(WhereExpression expression) {
    QueryRequest request;
    request.where.push_back(std::move(expression));
    return request;
  }

  Catalogue catalogue_ = Catalogue::Open(":memory:");
  CatalogueInspector inspector_{catalogue_};
  ArrayId array_{};
  ConfigId config_{}, other_config_{};
};

TEST_F(QueryRequestTest, QueryFieldsAreTheColumnsOfEachQuery) {
  for (const QueryKind kind : {QueryKind::kTests, QueryKind::kHic, QueryKind::kRotation, QueryKind::kCriteria,
                               QueryKind::kQuality}) {
    std::vector<std::string> names;
    for (const QueryField& field : QueryFields(kind)) names.push_back(field.name);
    EXPECT_EQ(names, catalogue_.Query(kind).columns);
  }
  for (const QueryField& field : QueryFields(QueryKind::kCriteria))
    EXPECT_EQ(field.numeric, field.name != "test_id" && field.name != "series" && field.name != "variant")
        << field.name;
  for (const QueryField& field : QueryFields(QueryKind::kQuality)) EXPECT_FALSE(field.numeric) << field.name;
}

TEST_F(QueryRequestTest, NumbersCompareNumericallyAndNullMatchesNothing) {
  using Op = ComparisonOperator;
  // Latest results: a1 700, a2 650 (other config), a3 NULL, a4 500.
  EXPECT_THAT(Ids(Where(Compare("hic15", Op::kGreater, 600.0))), ElementsAre("a1", "a2"));
  EXPECT_THAT(Ids(Where(Compare("hic15", Op::kGreaterEqual, 700.0))), ElementsAre("a1"));
  EXPECT_THAT(Ids(Where(Compare("hic15", Op::kLess, 650.0))), ElementsAre("a4"));
  EXPECT_THAT(Ids(Where(Compare("hic15", Op::kLessEqual, 650.0))), ElementsAre("a2", "a4"));
  EXPECT_THAT(Ids(Where(Compare("hic15", Op::kEqual, 500.0))), ElementsAre("a4"));
  EXPECT_THAT(Ids(Where(Compare("hic15", Op::kNotEqual, 500.0))), ElementsAre("a1", "a2"))
      << "a3's NULL hic15 matches neither = nor !=";
  // 9 is numerically below 10 (as text, "9" > "10"): a1's hic36 is 10 + 3.
  EXPECT_THAT(Ids(Where(Compare("hic36", Op::kGreater, 9.0))), ElementsAre("a1", "a2", "a3", "a4"));
  EXPECT_THAT(Ids(Where(Compare("series", Op::kNotEqual, std::string("sled")))), ElementsAre("a3"))
      << "a4 has no series: NULL matches nothing";
}

TEST_F(QueryRequestTest, AndOrTreesAndSeveralWhereExpressions) {
  using Op = ComparisonOperator;
  using Kind = WhereJunction::Kind;
  // hic15 > 600 or (variant = B and series = sled) ... or a4 by id.
  const WhereExpression tree =
      Junction(Kind::kOr, {Compare("hic15", Op::kGreater, 680.0),
                           Junction(Kind::kAnd, {Compare("variant", Op::kEqual, std::string("B")),
                                                 Compare("series", Op::kEqual, std::string("sled"))}),
                           Compare("test_id", Op::kEqual, std::string("a3"))});
  EXPECT_THAT(Ids(Where(tree)), ElementsAre("a1", "a2", "a3"));
  QueryRequest both = Where(tree);
  both.where.push_back(Compare("variant", Op::kEqual, std::string("A")));  // ANDed
  EXPECT_THAT(Ids(both), ElementsAre("a1", "a3"));
}

TEST_F(QueryRequestTest, SqlInValuesIsAValueAndLeavesTheCatalogueAlone) {
  const std::string hostile_series = "x'); DROP TABLE tests;--";
  const TestId hostile = test_support::AddTest(catalogue_, array_, "h1", hostile_series, "A\" OR 1=1 --");
  catalogue_.WriteResult(hostile, config_, Summary(60, 321), "exact");
  const std::string before = inspector_.Dump();

  QueryRequest request = Where(Compare("series", ComparisonOperator::kEqual, hostile_series));
  const Table table = catalogue_.Query(QueryKind::kCriteria, request);
  ASSERT_EQ(table.rows.size(), 1u);
  EXPECT_EQ(std::get<std::string>(table.rows[0][0]), "h1");
  EXPECT_EQ(std::get<std::string>(table.rows[0][1]), hostile_series);
  EXPECT_EQ(std::get<double>(table.rows[0][3]), 321.0);
  EXPECT_THAT(Ids(Where(Compare("variant", ComparisonOperator::kEqual, std::string("A\" OR 1=1 --")))),
              ElementsAre("h1"));
  QueryRequest by_label;
  by_label.tests.series = {hostile_series};
  by_label.tests.variants = {"' OR ''='"};
  EXPECT_THAT(Ids(by_label), IsEmpty());
  EXPECT_EQ(inspector_.Dump(), before) << "the catalogue is unchanged";
  EXPECT_EQ(catalogue_.Query(QueryKind::kTests).rows.size(), 6u);
}

TEST_F(QueryRequestTest, SortKeysThenTestIdWithNullsLast) {
  QueryRequest request;
  request.sort = {{"hic15", true}};
  EXPECT_THAT(Ids(request), ElementsAre("a1", "a2", "a4", "a3"));
  request.sort = {{"hic15", false}};
  EXPECT_THAT(Ids(request), ElementsAre("a4", "a2", "a1", "a3")) << "NULL last ascending too";
  request.sort = {{"variant", false}, {"hic15", true}};
  EXPECT_THAT(Ids(request), ElementsAre("a1", "a3", "a2", "a4"));
  request.sort = {{"variant", true}};
  EXPECT_THAT(Ids(request), ElementsAre("a2", "a4", "a1", "a3")) << "ties in test id order";
  request.sort = {{"series", false}};
  EXPECT_THAT(Ids(request), ElementsAre("a1", "a2", "a3", "a4")) << "a4 without a series comes last";
}

TEST_F(QueryRequestTest, LimitCutsAfterSorting) {
  QueryRequest request;
  request.sort = {{"hic15", true}};
  request.limit = 2;
  EXPECT_THAT(Ids(request), ElementsAre("a1", "a2"));
  request.limit = 0;
  const Table none = catalogue_.Query(QueryKind::kHic, request);
  EXPECT_THAT(none.rows, IsEmpty());
  EXPECT_EQ(none.columns, catalogue_.Query(QueryKind::kHic).columns);
  request.limit = 100;
  EXPECT_EQ(Ids(request).size(), 4u);
  request.limit = -1;
  EXPECT_THROW(catalogue_.Query(QueryKind::kHic, request), UsageError);
}

TEST_F(QueryRequestTest, ConfigSelectsThatResultSetForEveryKind) {
  QueryRequest request;
  request.config = config_;
  const Table hic = catalogue_.Query(QueryKind::kHic, request);
  ASSERT_EQ(hic.rows.size(), 4u);
  EXPECT_EQ(hic.columns, catalogue_.Query(QueryKind::kHic).columns);
  EXPECT_EQ(std::get<std::string>(hic.rows[1][0]), "a2");
  EXPECT_EQ(std::get<double>(hic.rows[1][3]), 900.0) << "a2 under the default config, not its latest";
  EXPECT_EQ(std::get<double>(hic.rows[1][4]), 20.0 + 1.0) << "hic15_t1_s, the next field";

  request.config = other_config_;
  EXPECT_THAT(Ids(request, QueryKind::kHic), ElementsAre("a2"));
  EXPECT_THAT(Ids(request, QueryKind::kTests), ElementsAre("a2")) << "tests with a result of the config";
  const Table rotation = catalogue_.Query(QueryKind::kRotation, request);
  ASSERT_EQ(rotation.rows.size(), 1u);
  EXPECT_EQ(rotation.columns, catalogue_.Query(QueryKind::kRotation).columns);
  const Table criteria = catalogue_.Query(QueryKind::kCriteria, request);
  EXPECT_EQ(criteria.columns, catalogue_.Query(QueryKind::kCriteria).columns);
  const Table quality = catalogue_.Query(QueryKind::kQuality, request);
  ASSERT_EQ(quality.rows.size(), 1u);
  EXPECT_EQ(quality.columns, catalogue_.Query(QueryKind::kQuality).columns);
  EXPECT_EQ(std::get<std::string>(quality.rows[0][6]), "Offset removed at 50.000000.");

  request.config = config_;
  request.where.push_back(Compare("hic15", ComparisonOperator::kGreater, 800.0));
  EXPECT_THAT(Ids(request), ElementsAre("a2"));
  request.where = {
      Compare("detail", ComparisonOperator::kEqual, std::string("Offset removed at 20.000000."))};
  EXPECT_THAT(Ids(request, QueryKind::kQuality), ElementsAre("a2"));
}

TEST_F(QueryRequestTest, RepeatedSeriesAndVariantsMatchAnyWithinAndAllAcross) {
  QueryRequest request;
  request.tests.series = {"sled", "tower"};
  EXPECT_THAT(Ids(request, QueryKind::kTests), ElementsAre("a1", "a2", "a3", "a5"));
  request.tests.variants = {"B"};
  EXPECT_THAT(Ids(request, QueryKind::kTests), ElementsAre("a2"));
  request.tests.series.clear();
  request.tests.variants = {"A", "B"};
  EXPECT_THAT(Ids(request, QueryKind::kTests), ElementsAre("a1", "a2", "a3", "a4", "a5"));
  request.tests.external_ids = {"a4", "a5"};
  EXPECT_THAT(Ids(request, QueryKind::kTests), ElementsAre("a4", "a5"));
}

TEST_F(QueryRequestTest, UnknownFieldsAndMismatchedValuesAreRefused) {
  using Op = ComparisonOperator;
  EXPECT_THAT(
      [&] { catalogue_.Query(QueryKind::kHic, Where(Compare("bric", Op::kGreater, 1.0))); },
      ThrowsMessage<UsageError>(HasSubstr("--where names unknown field 'bric'; the fields of query hic are "
                                          "test_id, series, variant, hic15")));
  EXPECT_THAT(
      [&] { catalogue_.Query(QueryKind::kHic, Where(Compare("hic15", Op::kGreater, std::string("1")))); },
      ThrowsMessage<UsageError>(HasSubstr("compares numeric field 'hic15' with text")));
  EXPECT_THAT([&] { catalogue_.Query(QueryKind::kTests, Where(Compare("series", Op::kEqual, 1.0))); },
              ThrowsMessage<UsageError>(HasSubstr("compares text field 'series' with a number")));
  QueryRequest sort;
  sort.sort = {{"hic15; DROP TABLE tests", false}};
  EXPECT_THAT([&] { catalogue_.Query(QueryKind::kHic, sort); },
              ThrowsMessage<UsageError>(HasSubstr("--sort names unknown field 'hic15; DROP TABLE tests'")));
  EXPECT_EQ(catalogue_.Query(QueryKind::kTests).rows.size(), 5u);
}

TEST_F(QueryRequestTest, ReadAllConfigsInWriteOrder) {
  const std::vector<ConfigRow> configs = catalogue_.ReadAllConfigs();
  ASSERT_EQ(configs.size(), 2u);
  EXPECT_EQ(configs[0].id, config_);
  EXPECT_EQ(configs[1].id, other_config_);
  EXPECT_EQ(configs[1].config_json, R"({"filter":"cfc180"})");
  EXPECT_EQ(configs[1].config_hash, test_support::DefaultConfig(R"({"filter":"cfc180"})").config_hash);
}

}  // namespace
}  // namespace napkin::db
