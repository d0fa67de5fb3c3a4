// Catalogue: stored ISO/TS 18571 ratings (schema/009_correlation.sql):
// round trip, replacement by the same reference and parameters, ratings
// dropped with the result they rated, and `query correlation`.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "common/error.h"
#include "db/catalogue.h"
#include "db/job_queue.h"
#include "db/results_file.h"
#include "schema/migrations.h"
#include "tests/db/db_test_helpers.h"
#include "tests/support/db/catalogue_inspector.h"
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
  CorrelationRow Model(double overall) const {
    CorrelationRow record;
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
  CorrelationRow against_test = Model(1.0);
  against_test.reference_kind = "test";
  against_test.reference = "v0002";
  against_test.reference_key = "test:v0002";
  against_test.model_file = against_test.model_sha256 = against_test.model_column = std::nullopt;
  against_test.reference_test = other_;
  catalogue_.WriteCorrelation(against_test);
  catalogue_.WriteCorrelation(Model(0.79));  // the same model, column, edition and interval: replaced

  const std::vector<CorrelationRow> read = catalogue_.ReadCorrelations(test_, config_);
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[0].reference, "head.k:curve 4");  // by channel, then reference
  EXPECT_EQ(read[0].overall, 0.79);
  EXPECT_EQ(read[0].model_sha256, "abc");
  EXPECT_EQ(read[0].shift_s, -0.0002);
  EXPECT_EQ(read[1].reference_test, other_);
  EXPECT_EQ(read[1].model_file, std::nullopt);

  // Another interval is another rating.
  CorrelationRow shorter = Model(0.5);
  shorter.end_s = 0.05;
  catalogue_.WriteCorrelation(shorter);
  EXPECT_EQ(catalogue_.ReadCorrelations(test_, config_).size(), 3u);

  QueryRequest request;
  request.where.push_back(WhereExpression{WhereComparison{"overall", ComparisonOperator::kLess, 0.8}});
  const Table low = catalogue_.Query(QueryKind::kCorrelation, request);
  ASSERT_EQ(low.rows.size(), 2u);
  EXPECT_EQ(std::get<double>(low.rows[0][18]),
            0.5);  // overall; ordered by test, channel, reference, ..., end_s
  EXPECT_EQ(std::get<double>(low.rows[1][18]), 0.79);
  EXPECT_EQ(low.columns[18], "overall");
}

TEST_F(CorrelationTest, AResultComputedAgainDropsItsRatings) {
  catalogue_.WriteCorrelation(Model(0.78));
  catalogue_.WriteResult(test_, config_, {}, "exact");
  EXPECT_TRUE(catalogue_.ReadCorrelations(test_, config_).empty());
  EXPECT_TRUE(catalogue_.Query(QueryKind::kCorrelation).rows.empty());
}

TEST_F(CorrelationTest, ATestWithoutThatResultIsRefused) {
  CorrelationRow record = Model(0.5);
  record.test = other_;
  EXPECT_THROW(catalogue_.WriteCorrelation(record), InputError);
}

// The same curve rated under other model units is another rating, and says its units (issue 42,
// point 3: the second replaced the first and neither said which units it used).
TEST_F(CorrelationTest, OtherModelUnitsAreAnotherRatingThatSaysItsUnits) {
  CorrelationRow metres = Model(0.9);
  metres.model_units = "m,s,kg";
  metres.reference_key += ":units=m,s,kg";
  CorrelationRow millimetres = Model(0.3);
  millimetres.model_units = "mm,s,kg";
  millimetres.reference_key += ":units=mm,s,kg";
  catalogue_.WriteCorrelation(metres);
  catalogue_.WriteCorrelation(millimetres);
  const std::vector<CorrelationRow> read = catalogue_.ReadCorrelations(test_, config_);
  ASSERT_EQ(read.size(), 2u);
  std::set<std::optional<std::string>> units = {read[0].model_units, read[1].model_units};
  EXPECT_EQ(units, (std::set<std::optional<std::string>>{"m,s,kg", "mm,s,kg"}));
  const Table table = catalogue_.Query(QueryKind::kCorrelation);
  ASSERT_EQ(table.columns[9], "model_units");
  ASSERT_EQ(table.rows.size(), 2u);
}

// `merge` carries the shard's ratings with their identity, keeps the catalogue's own ratings of a
// result the shard's newer one replaces, and merging again changes nothing (issue 42, point 2:
// every rating of the shard was dropped, and so were the catalogue's of the replaced results).
// A rating of `test`'s acc_resultant_g under `config` against curve 4 of model "head.k" (sha256
// "abc") read in `units`, keyed as app/correlation.cpp keys it.
CorrelationRow ModelRating(TestId test, ConfigId config, const std::string& units, double overall) {
  CorrelationRow record;
  record.test = test;
  record.config = config;
  record.channel = "acc_resultant_g";
  record.reference_kind = "model";
  record.reference = "head.k:curve 4";
  record.reference_key = "model:abc:curve 4:units=" + units;
  record.model_file = "head.k";
  record.model_sha256 = "abc";
  record.model_column = "curve 4";
  record.model_units = units;
  record.edition = "2024";
  record.end_s = 0.1;
  record.overall = overall;
  record.grade = "fair";
  return record;
}

// `model` as a rating against test `reference` (its id `reference_id`).
CorrelationRow AgainstTest(CorrelationRow model, TestId reference, const std::string& reference_id) {
  model.reference_kind = "test";
  model.reference = reference_id;
  model.reference_key = "test:" + reference_id;
  model.model_file = model.model_sha256 = model.model_column = model.model_units = std::nullopt;
  model.reference_test = reference;
  return model;
}

TEST(CorrelationMerge, MergeCarriesRatingsAndKeepsTheCataloguesOwn) {
  test_support::TempDir dir;
  const std::string main_path = (dir.path() / "main.db").string();
  const std::string shard_path = (dir.path() / "shard.db").string();
  double now = 1000.0;
  CatalogueOptions options;
  options.clock = [&now] { return now += 1.0; };
  ConfigId config{};
  TestId v1{}, v2{};
  {
    Catalogue base = Catalogue::Open(main_path, options);
    const ArrayId array = base.WriteArray(test_support::IdealArray());
    config = base.WriteConfig(test_support::DefaultConfig());
    v1 = test_support::AddTest(base, array, "v0001");
    v2 = test_support::AddTest(base, array, "v0002");
    base.WriteResult(v1, config, {}, "exact");
    base.WriteResult(v2, config, {}, "exact");
  }
  std::filesystem::copy_file(main_path, shard_path);
  const auto rating = [&](TestId test, const std::string& units, double overall) {
    return ModelRating(test, config, units, overall);
  };
  {
    Catalogue shard = Catalogue::Open(shard_path, options);
    shard.WriteResult(v1, config, {}, "exact");  // the same values computed again, later
    shard.WriteCorrelation(rating(v1, "mm,s,kg", 0.3));
    shard.WriteCorrelation(AgainstTest(rating(v1, "", 0.95), v2, "v0002"));
    shard.WriteCorrelation(rating(v2, "m,s,kg", 0.7));
  }
  Catalogue catalogue = Catalogue::Open(main_path, options);
  catalogue.WriteCorrelation(rating(v1, "m,s,kg", 0.9));
  const MergeReport merged = catalogue.MergeShard(shard_path);
  EXPECT_EQ(merged.results_merged, 1);
  EXPECT_EQ(merged.ratings_merged, 3);
  const std::vector<CorrelationRow> v1_ratings = catalogue.ReadCorrelations(v1, config);
  ASSERT_EQ(v1_ratings.size(), 3u);
  std::set<std::pair<std::string, double>> seen;  // reference key, overall
  for (const CorrelationRow& record : v1_ratings) seen.insert({record.reference_key, record.overall});
  EXPECT_EQ(seen, (std::set<std::pair<std::string, double>>{{"model:abc:curve 4:units=m,s,kg", 0.9},
                                                            {"model:abc:curve 4:units=mm,s,kg", 0.3},
                                                            {"test:v0002", 0.95}}));
  for (const CorrelationRow& record : v1_ratings) {
    if (record.reference_kind == "test") {
      EXPECT_EQ(record.reference_test, v2);
    }
  }
  ASSERT_EQ(catalogue.ReadCorrelations(v2, config).size(), 1u);
  EXPECT_EQ(catalogue.ReadCorrelations(v2, config)[0].model_units, "m,s,kg");
  EXPECT_EQ(catalogue.MergeShard(shard_path).ratings_merged, 0);
  EXPECT_EQ(catalogue.ReadCorrelations(v1, config).size(), 3u);
}

// A results file (`run --results`) holding ratings: merge carries them onto the catalogue's tests,
// matched by content hash, with their identity, as it carries a shard's (issue 42, point 2).
TEST(CorrelationMerge, MergeCarriesTheRatingsOfAResultsFile) {
  test_support::TempDir dir;
  const std::string main_path = (dir.path() / "main.db").string();
  const std::string results_path = (dir.path() / "results.db").string();
  TestId v1{}, v2{};
  {
    Catalogue base = Catalogue::Open(main_path);
    const ArrayId array = base.WriteArray(test_support::IdealArray());
    v1 = test_support::AddTest(base, array, "v0001");
    v2 = test_support::AddTest(base, array, "v0002");
  }
  {
    Catalogue shared = ResultsFile::OpenSharedCatalogue(main_path);
    Catalogue results = ResultsFile::Open(results_path, shared);
    ASSERT_EQ(ResultsFile::CopyTests(shared, results, JobScope{}), 2);
    const ConfigId config = results.WriteConfig(test_support::DefaultConfig());
    results.WriteResult(v1, config, {}, "exact");
    results.WriteResult(v2, config, {}, "exact");
    CorrelationRow model = ModelRating(v1, config, "mm,s,kg", 0.42);
    model.edition = "2014";
    model.start_s = 0.01;
    model.grade = "poor";
    results.WriteCorrelation(model);
    CorrelationRow against = AgainstTest(ModelRating(v1, config, "", 0.97), v2, "v0002");
    against.grade = "excellent";
    results.WriteCorrelation(against);
  }
  Catalogue catalogue = Catalogue::Open(main_path);
  const MergeReport merged = catalogue.MergeShard(results_path);
  EXPECT_EQ(merged.results_merged, 2);
  EXPECT_EQ(merged.ratings_merged, 2);
  const std::optional<ConfigId> config =
      catalogue.FindConfigByHash(test_support::DefaultConfig().config_hash);
  ASSERT_TRUE(config);
  const std::vector<CorrelationRow> ratings = catalogue.ReadCorrelations(v1, *config);
  ASSERT_EQ(ratings.size(), 2u);
  std::map<std::string, const CorrelationRow*> by_key;
  for (const CorrelationRow& rating : ratings) by_key[rating.reference_key] = &rating;
  ASSERT_TRUE(by_key.count("model:abc:curve 4:units=mm,s,kg"));
  const CorrelationRow& model = *by_key["model:abc:curve 4:units=mm,s,kg"];
  EXPECT_EQ(model.model_units, "mm,s,kg");
  EXPECT_EQ(model.model_sha256, "abc");
  EXPECT_EQ(model.edition, "2014");
  EXPECT_EQ(model.start_s, 0.01);
  EXPECT_EQ(model.end_s, 0.1);
  EXPECT_EQ(model.overall, 0.42);
  ASSERT_TRUE(by_key.count("test:v0002"));
  EXPECT_EQ(by_key["test:v0002"]->reference_test, v2);
  EXPECT_EQ(by_key["test:v0002"]->overall, 0.97);
  EXPECT_EQ(catalogue.MergeShard(results_path).ratings_merged, 0) << "merging it again adds nothing";
}

// Test-against-test ratings stored before schema 11 took the roles the wrong way round: marked on
// upgrade, never left looking like a rating made now (issue 42, point 15).
TEST(CorrelationMigration, TestRatingsOfTheOldRolesAreMarked) {
  test_support::TempDir dir;
  const std::string path = (dir.path() / "v10.db").string();
  TestId v1{}, v2{};
  ConfigId config{};
  {
    CatalogueOptions first_ten;
    first_ten.migrations = schema::Migrations().first(10);
    Catalogue catalogue = Catalogue::Open(path, first_ten);
    const ArrayId array = catalogue.WriteArray(test_support::IdealArray());
    config = catalogue.WriteConfig(test_support::DefaultConfig());
    v1 = test_support::AddTest(catalogue, array, "v0001");
    v2 = test_support::AddTest(catalogue, array, "v0002");
    // As a catalogue of schema 10 held it: today's WriteResult writes tables of later versions.
    auto result = CatalogueInspector(catalogue).connection().Prepare(
        "INSERT INTO results (test_id, config_id, solver, computed_at) VALUES (?1, ?2, 'exact', "
        "'2026-01-01T00:00:00Z')");
    result->Bind(1, v1);
    result->Bind(2, config);
    result->Execute();
    for (const TestId reference : {v2, v1}) {
      CorrelationRow record;
      record.test = v1;
      record.config = config;
      record.channel = "acc_resultant_g";
      record.reference_kind = "test";
      record.reference = reference == v2 ? "v0002" : "v0001";
      record.reference_key = "test:" + record.reference;
      record.reference_test = reference;
      record.edition = "2024";
      record.end_s = 0.1;
      record.overall = 0.8;
      record.grade = "fair";
      catalogue.WriteCorrelation(record);
    }
  }
  Catalogue catalogue = Catalogue::Open(path);
  std::map<std::string, std::string> reference_by_key;
  for (const CorrelationRow& record : catalogue.ReadCorrelations(v1, config))
    reference_by_key[record.reference_key] = record.reference;
  EXPECT_EQ(reference_by_key,
            (std::map<std::string, std::string>{
                {"test-swapped:v0002",
                 "v0002 (rated before schema 11 with the roles swapped: this test was the candidate)"},
                {"test:v0001", "v0001"}}));
}

}  // namespace
}  // namespace napkin::db
