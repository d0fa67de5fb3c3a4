// Catalogue: stored ISO/TS 18571 ratings (schema/009_correlation.sql):
// round trip, replacement by the same reference and parameters, ratings
// dropped with the result they rated, and `query correlation`.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/error.h"
#include "db/catalogue.h"
#include "tests/db/db_test_helpers.h"
#include "tests/support/test_support.h"

namespace napkin::db {
namespace {

class CorrelationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    array_ = catalogue_.WriteArray(test_support::IdealArray());
    config_ = catalogue_.WriteConfig(test_support::DefaultConfig());
    test_ = test_support::AddTest(catalogue_, array_, "v0001");
    other_ = test_support::AddTest(catalogue_, array_, "v0002");
    catalogue_.WriteResult(test_, config_, {}, "exact");
  }
  CorrelationRecord Model(double overall) const {
    CorrelationRecord record;
    record.test = test_;
    record.config = config_;
    record.channel = "acc_resultant_g";
    record.reference_kind = "model";
    record.reference = "head.k:curve 4";
    record.reference_key = "model:abc:curve 4";
    record.model_file = "head.k";
    record.model_sha256 = "abc";
    record.model_column = "curve 4";
    record.edition = "2024";
    record.start_s = 0.0;
    record.end_s = 0.1;
    record.corridor = 0.9;
    record.phase = 0.8;
    record.magnitude = 0.7;
    record.slope = 0.6;
    record.overall = overall;
    record.grade = "fair";
    record.shift_s = -0.0002;
    return record;
  }
  Catalogue catalogue_ = Catalogue::Open(":memory:");
  ArrayId array_{};
  ConfigId config_{};
  TestId test_{}, other_{};
};

TEST_F(CorrelationTest, RoundTripsAndReplacesTheSameReference) {
  catalogue_.WriteCorrelation(Model(0.78));
  CorrelationRecord against_test = Model(1.0);
  against_test.reference_kind = "test";
  against_test.reference = "v0002";
  against_test.reference_key = "test:v0002";
  against_test.model_file = against_test.model_sha256 = against_test.model_column = std::nullopt;
  against_test.reference_test = other_;
  catalogue_.WriteCorrelation(against_test);
  catalogue_.WriteCorrelation(Model(0.79));  // the same model, column, edition and interval: replaced

  const std::vector<CorrelationRecord> read = catalogue_.ReadCorrelations(test_, config_);
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[0].reference, "head.k:curve 4");  // by channel, then reference
  EXPECT_EQ(read[0].overall, 0.79);
  EXPECT_EQ(read[0].model_sha256, "abc");
  EXPECT_EQ(read[0].shift_s, -0.0002);
  EXPECT_EQ(read[1].reference_test, other_);
  EXPECT_EQ(read[1].model_file, std::nullopt);

  // Another interval is another rating.
  CorrelationRecord shorter = Model(0.5);
  shorter.end_s = 0.05;
  catalogue_.WriteCorrelation(shorter);
  EXPECT_EQ(catalogue_.ReadCorrelations(test_, config_).size(), 3u);

  QueryRequest request;
  request.where.push_back(WhereExpression{WhereComparison{"overall", ComparisonOperator::kLess, 0.8}});
  const Table low = catalogue_.Query(QueryKind::kCorrelation, request);
  ASSERT_EQ(low.rows.size(), 2u);
  EXPECT_EQ(std::get<double>(low.rows[0][17]),
            0.5);  // overall; ordered by test, channel, reference, ..., end_s
  EXPECT_EQ(std::get<double>(low.rows[1][17]), 0.79);
  EXPECT_EQ(low.columns[17], "overall");
}

TEST_F(CorrelationTest, AResultComputedAgainDropsItsRatings) {
  catalogue_.WriteCorrelation(Model(0.78));
  catalogue_.WriteResult(test_, config_, {}, "exact");
  EXPECT_TRUE(catalogue_.ReadCorrelations(test_, config_).empty());
  EXPECT_TRUE(catalogue_.Query(QueryKind::kCorrelation).rows.empty());
}

TEST_F(CorrelationTest, ATestWithoutThatResultIsRefused) {
  CorrelationRecord record = Model(0.5);
  record.test = other_;
  EXPECT_THROW(catalogue_.WriteCorrelation(record), InputError);
}

}  // namespace
}  // namespace napkin::db
