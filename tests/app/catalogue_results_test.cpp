// The application library on a catalogue of processed tests, called
// directly (no command line): which result of a test a choice names
// (app/result_selection.h, docs/architecture.md "Which result of a test"),
// the kinematics of a result stored or recomputed (bit for bit those a
// float64 run stores), and ISO/TS 18571 ratings (app/correlation.h): a test
// against itself and against its own channel written as a model rate exactly
// 1, the same model in the wrong --model-units is refused saying the time
// range those units give it, and every rating is stored; a query's rows are
// the stored summaries (app/query.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <limits>
#include <string>
#include <variant>
#include <vector>

#include "app/correlation.h"
#include "app/query.h"
#include "app/result_selection.h"
#include "common/error.h"
#include "records/config_record.h"
#include "tests/app/app_test_util.h"
#include "tests/jobs/jobs_test_helpers.h"
#include "tests/support/test_support.h"
#include "util/text.h"

namespace napkin::app {
namespace {

// A config's run over the catalogue, under `name`.
jobs::RunReport RunConfig(const std::string& path, engine::DerivedStorage storage, const std::string& name) {
  engine::ProcessingConfig config;
  config.storage.derived_channels = storage;
  jobs::RunOptions options;
  options.threads = 1;
  options.poll_interval_s = 0.05;
  return jobs::RunScheduler(path, records::ResolvedConfig{config, records::MakeConfigRecord(config, name)},
                            options);
}

// Three random motions run under a float64 config ("float64"), then under one that stores no
// derived channels ("none", the latest result); a fourth test stored after without a result.
class AppOnCatalogue : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test_support::TempDir;
    path_ = (*dir_ / "catalogue.db").string();
    test_support::AddRandomTests(path_, 3, 1000);
    float64_ = RunConfig(path_, engine::DerivedStorage::kFloat64, "float64").config;
    none_ = RunConfig(path_, engine::DerivedStorage::kNone, "none").config;
    test_support::AddRandomTests(path_, 1, 1000, 3);
  }
  static void TearDownTestSuite() { delete dir_; }

  static test_support::TempDir* dir_;
  static std::string path_;
  static db::ConfigId float64_, none_;
};
test_support::TempDir* AppOnCatalogue::dir_ = nullptr;
std::string AppOnCatalogue::path_;
db::ConfigId AppOnCatalogue::float64_{}, AppOnCatalogue::none_{};

TEST_F(AppOnCatalogue, EachChoiceNamesItsResult) {
  db::Catalogue catalogue = db::Catalogue::Open(path_);
  ASSERT_NE(float64_, none_);
  const std::string test = test_support::TestName(1);
  EXPECT_EQ(ResultOf(catalogue, test, Latest{}).config, none_);  // the result written last
  EXPECT_EQ(ResultOf(catalogue, test, Stored{"float64"}).config, float64_);
  const std::string none_hash = catalogue.ReadConfig(none_).config_hash;
  EXPECT_EQ(ResultOf(catalogue, test, Stored{util::ToUpper(none_hash.substr(0, 10))}).config, none_);
  EXPECT_EQ(ResultOf(catalogue, test, Stored{"none"}).test, *catalogue.FindTestByExternalId(test));
  EXPECT_THROW(ResultOf(catalogue, test, Stored{"nope"}), UsageError);
  EXPECT_EQ(test_support::ErrorText<NotFoundError>([&] { ResultOf(catalogue, "missing", Latest{}); }),
            "test 'missing' is not in catalogue '" + path_ + "'.");
  const std::string unrun = test_support::TestName(3);
  EXPECT_EQ(test_support::ErrorText<InputError>([&] { ResultOf(catalogue, unrun, Latest{}); }),
            "test '" + unrun + "' has no results yet; run `napkin run` first.");
  EXPECT_FALSE(FindResult(catalogue, *catalogue.FindTestByExternalId(unrun), Stored{"float64"}));
}

TEST(ConfigSelector, ANameExactlyElseOneHashPrefix) {
  std::vector<db::ConfigRow> configs(3);
  configs[0].name = "default";
  configs[0].config_hash = "ab12cd";
  configs[1].name = "cfc180";
  configs[1].config_hash = "ab34ef";
  configs[2].name = "default";
  configs[2].config_hash = "9f0000";
  EXPECT_EQ(MatchConfigSelector(configs, "--config", "cfc180"), 1u);
  EXPECT_EQ(MatchConfigSelector(configs, "--config", "AB3"), 1u);  // case-insensitive
  EXPECT_EQ(MatchConfigSelector(configs, "--config", "9f"), 2u);
  EXPECT_NE(test_support::ErrorText<UsageError>([&] {
              MatchConfigSelector(configs, "--config", "default");
            }).find("give a hash prefix instead"),
            std::string::npos);
  EXPECT_THROW(MatchConfigSelector(configs, "--config", "ab"), UsageError);  // two hashes start so
  EXPECT_THROW(MatchConfigSelector(configs, "--config", ""), UsageError);
  EXPECT_THROW(MatchConfigSelector(configs, "--config", "zz"), UsageError);
}

// A result stored as float64 is read as stored; one without stored channels is recomputed from
// the test's inputs, bit for bit the float64 run's.
TEST_F(AppOnCatalogue, AResultsKinematicsStoredOrRecomputedAreThoseOfTheRun) {
  db::Catalogue catalogue = db::Catalogue::Open(path_);
  EXPECT_FALSE(catalogue.ReadKinematics(*catalogue.FindTestByExternalId(test_support::TestName(0)), none_));
  for (int i = 0; i < 3; ++i) {
    const db::TestId test = *catalogue.FindTestByExternalId(test_support::TestName(i));
    const std::optional<engine::Kinematics> stored = catalogue.ReadKinematics(test, float64_);
    ASSERT_TRUE(stored);
    test_support::ExpectSameKinematics(*stored, ReadResultKinematics(catalogue, test, float64_),
                                       test_support::TestName(i));
    test_support::ExpectSameKinematics(*stored, ReadResultKinematics(catalogue, test, none_),
                                       test_support::TestName(i));
  }
}

// The channel's own samples as a keyword curve (comma-separated, every digit of each double):
// read in m, s, kg they are the channel, and the rating is that of the test against itself.
TEST_F(AppOnCatalogue, ATestAgainstItselfAndItsOwnCurveAsAModelRatesOne) {
  db::Catalogue catalogue = db::Catalogue::Open(path_);
  const std::string test = test_support::TestName(2);
  RatingOptions options;
  options.channel = "acc_resultant_g";
  const std::size_t stored_before =
      catalogue.ReadCorrelations(*catalogue.FindTestByExternalId(test), none_).size();
  const RatingRow self = RateAgainstTest(catalogue, test, test, options);
  for (const double score : {self.rating.corridor, self.rating.phase, self.rating.magnitude,
                             self.rating.slope, self.rating.overall})
    EXPECT_EQ(score, 1.0);
  EXPECT_EQ(self.rating.shift_s, 0.0);
  EXPECT_EQ(self.reference, test);

  const TestResult result = ResultOf(catalogue, test, Latest{});
  const ChannelCurve channel =
      ChannelOf(ReadResultKinematics(catalogue, result.test, result.config), options.channel, test);
  std::string keyword = "*KEYWORD\n*DEFINE_CURVE\n7\n";
  for (Eigen::Index k = 0; k < channel.series.time_s.size(); ++k)
    keyword += util::FormatNumber(channel.series.time_s(k)) + "," +
               util::FormatNumber(channel.series.values(k)) + "\n";
  const std::string model = (*dir_ / "self.k").string();
  std::ofstream(model, std::ios::binary) << keyword + "*END\n";
  const ModelReference read = LoadModelCurve(model + ":7", channel, std::string("m,s,kg"));
  EXPECT_EQ(read.series.time_s, channel.series.time_s);
  EXPECT_EQ(read.series.values, channel.series.values);
  const RatingRow against_model = RateAgainstModel(catalogue, test, model + ":7", "m,s,kg", options);
  EXPECT_EQ(against_model.rating.overall, 1.0);
  EXPECT_EQ(against_model.rating.grade, engine::Iso18571Grade::kExcellent);
  EXPECT_EQ(against_model.reference, "self.k:curve 7");

  // The same numbers taken as microseconds: the model's time range under those units is said, with
  // the units, and that it covers a sliver of the test.
  const double first_us = channel.series.time_s(0) * 1e-6;
  const double last_us = channel.series.time_s(channel.series.time_s.size() - 1) * 1e-6;
  const std::string refused = test_support::ErrorText<InputError>(
      [&] { RateAgainstModel(catalogue, test, model + ":7", "m,us,kg", options); });
  EXPECT_NE(refused.find("curve 'curve 7' (read in --model-units m,us,kg) runs from " +
                         util::FormatNumber(first_us, 4) + " to " + util::FormatNumber(last_us, 4) +
                         " s, which covers"),
            std::string::npos)
      << refused;
  EXPECT_NE(refused.find("give --start and --end"), std::string::npos) << refused;
  EXPECT_EQ(catalogue.ReadCorrelations(*catalogue.FindTestByExternalId(test), none_).size(),
            stored_before + 2);
}

// A query's rows are the catalogue's stored summaries: --where, --sort and --limit select and order
// them, and --config picks the result (each test's latest without it).
TEST_F(AppOnCatalogue, AQuerysRowsAreTheStoredSummaries) {
  db::Catalogue catalogue = db::Catalogue::Open(path_);
  Query query;
  query.kind = "hic";
  query.filters.config = "float64";
  query.filters.sort = {"hic15:desc"};
  const db::Table all = RunQuery(catalogue, PrepareQuery(query));
  ASSERT_EQ(all.rows.size(), 3u);  // the fourth test has no result
  const auto column = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(all.columns.begin(), all.columns.end(), name) -
                                    all.columns.begin());
  };
  ASSERT_LT(column("hic15"), all.columns.size());
  double previous = std::numeric_limits<double>::infinity();
  for (const std::vector<db::Cell>& row : all.rows) {
    const std::string test = std::get<std::string>(row[column("test_id")]);
    const double hic15 = std::get<double>(row[column("hic15")]);
    const std::optional<engine::TestSummary> summary =
        catalogue.ReadSummary(*catalogue.FindTestByExternalId(test), float64_);
    ASSERT_TRUE(summary) << test;
    EXPECT_EQ(hic15, summary->hic15.value) << test;
    EXPECT_LE(hic15, previous) << test;
    previous = hic15;
  }
  query.filters.where = {"test_id=" + test_support::TestName(1)};
  query.filters.limit = "1";
  const db::Table one = RunQuery(catalogue, PrepareQuery(query));
  ASSERT_EQ(one.rows.size(), 1u);
  EXPECT_EQ(std::get<std::string>(one.rows[0][column("test_id")]), test_support::TestName(1));
  query.kind = "everything";
  EXPECT_THROW(PrepareQuery(query), UsageError);
}

}  // namespace
}  // namespace napkin::app
