// `napkin correlate` end to end (issue 32 point 3; docs/formats.md
// "Correlation ratings"): a test against its own exports read back as a
// model (LS-DYNA keyword, derived-channel CSV) and against itself rates
// 1, a model scaled out of the corridors rates below; every rating is
// stored and `query correlation --where` selects them; each repeat of a
// variant against its mean; bad model files are refused in one sentence
// naming the file; `report --model` draws the ratings with their corridors.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "app/correlation.h"
#include "common/error.h"
#include "formats/model_curves.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"
#include "util/text.h"

namespace napkin {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test_support::RunResult;
using ::testing::HasSubstr;

// One catalogue for the suite: padding-series, 2 repeats of 3 variants (100 ms
// at 10 kHz), run.
class CorrelateCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test_support::TempDir;
    for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
             {"synth", "--scenario", "padding-series", "--count", "2", "--rate", "10000"}, {"run"}}) {
      const RunResult result = Napkin(args);
      if (result.exit_code != 0 && setup_error_.empty())
        setup_error_ =
            "napkin " + args.front() + " exited " + std::to_string(result.exit_code) + ": " + result.err;
    }
    if (!setup_error_.empty()) return;
    const RunResult tests = Napkin({"query", "tests", "--variant", "foam-a", "--format", "json"});
    for (const json& test : json::parse(tests.out)) foam_a_.push_back(test.at("test_id").get<std::string>());
  }
  static void TearDownTestSuite() { delete dir_; }
  void SetUp() override {
    ASSERT_EQ(setup_error_, "") << "the suite's catalogue could not be built";
    ASSERT_EQ(foam_a_.size(), 2u);
  }

  static RunResult Napkin(const std::vector<std::string>& args) {
    return test_support::RunNapkin(dir_->path(), args);
  }
  // `napkin correlate ARGS --format json`: its one row.
  static json RateOne(std::vector<std::string> args) {
    args.insert(args.begin(), "correlate");
    args.insert(args.end(), {"--format", "json"});
    const RunResult run = Napkin(args);
    EXPECT_EQ(run.exit_code, 0) << run.err;
    const json rows = json::parse(run.out, nullptr, false);
    EXPECT_TRUE(rows.is_array() && rows.size() == 1) << run.out;
    return rows.is_array() && rows.size() == 1 ? rows[0] : json::object();
  }

  static test_support::TempDir* dir_;
  static std::string setup_error_;
  static std::vector<std::string> foam_a_;
};
test_support::TempDir* CorrelateCli::dir_ = nullptr;
std::string CorrelateCli::setup_error_;
std::vector<std::string> CorrelateCli::foam_a_;

void ExpectAllOne(const json& row) {
  for (const char* score : {"corridor", "phase", "magnitude", "slope", "overall"})
    EXPECT_EQ(row.at(score).get<double>(), 1.0) << score << " " << row.dump();
  EXPECT_EQ(row.at("grade"), "excellent");
  EXPECT_EQ(row.at("shift_s").get<double>(), 0.0);
}

TEST_F(CorrelateCli, TestAgainstItselfRatesOne) {
  const std::string& test = foam_a_[0];
  for (const char* channel : {"acc_resultant_g", "omega_body_y_radps", "alpha_resultant_radps2"}) {
    const json row = RateOne({"--test", test, "--reference-test", test, "--channel", channel});
    ExpectAllOne(row);
    EXPECT_EQ(row.at("reference"), test);
    EXPECT_EQ(row.at("channel"), channel);
    EXPECT_EQ(row.at("edition"), "2024");
    // The interval defaults to the whole common span: 100 ms at 10 kHz.
    EXPECT_NEAR(row.at("end_s").get<double>() - row.at("start_s").get<double>(), 0.1, 1e-9);
  }
}

// napkin's own LS-DYNA export (angular velocity about fixed X, Y, Z as
// curves 4-6, in m, s) read back as the model rates 1.000; without
// --model-units the keyword file is refused.
TEST_F(CorrelateCli, LsDynaExportReadBackAsModelRatesOne) {
  const std::string& test = foam_a_[0];
  const RunResult exported =
      Napkin({"export", "--test", test, "--format", "lsdyna", "--units", "si", "--out", "head.k"});
  ASSERT_EQ(exported.exit_code, 0) << exported.err;
  for (const auto& [curve, channel] : std::vector<std::pair<std::string, std::string>>{
           {"4", "omega_fixed_x_radps"}, {"5", "omega_fixed_y_radps"}, {"6", "omega_fixed_z_radps"}}) {
    const json row = RateOne(
        {"--test", test, "--channel", channel, "--model", "head.k:" + curve, "--model-units", "m,s,kg"});
    // The keyword's 20-column numbers hold about 13 significant digits.
    for (const char* score : {"corridor", "phase", "magnitude", "slope", "overall"})
      EXPECT_NEAR(row.at(score).get<double>(), 1.0, 5e-4) << channel << " " << score;
    EXPECT_EQ(row.at("grade"), "excellent");
    EXPECT_THAT(row.at("reference").get<std::string>(), HasSubstr("head.k:curve " + curve));
  }
  const RunResult no_units =
      Napkin({"correlate", "--test", test, "--channel", "omega_fixed_x_radps", "--model", "head.k:4"});
  EXPECT_EQ(no_units.exit_code, 2);
  test_support::ExpectOneSentenceError(no_units, {"model file 'head.k'", "--model-units"});
}

// The test named --reference-test is the reference curve: rating A against reference B is rating
// A's exported channel as the candidate against B (a model is always the candidate), and the two
// directions differ (issue 42, point 15: B was rated against A while `reference` named B).
TEST_F(CorrelateCli, TheReferenceTestIsTheReferenceCurve) {
  const std::string& a = foam_a_[0];
  const std::string& b = foam_a_[1];
  const std::string channel = "acc_body_x_g";  // a column of the derived-channel CSV
  ASSERT_EQ(Napkin({"export", "--test", a, "--format", "csv", "--out", "candidate.csv"}).exit_code, 0);
  const json against_b = RateOne({"--test", a, "--reference-test", b, "--channel", channel});
  const json model = RateOne({"--test", b, "--model", "candidate.csv", "--channel", channel});
  for (const char* score : {"corridor", "phase", "magnitude", "slope", "overall", "shift_s"})
    EXPECT_NEAR(against_b.at(score).get<double>(), model.at(score).get<double>(), 1e-12) << score;
  EXPECT_EQ(against_b.at("reference"), b);
  const json against_a = RateOne({"--test", b, "--reference-test", a, "--channel", channel});
  EXPECT_NE(against_a.at("overall").get<double>(), against_b.at("overall").get<double>())
      << "the two directions agree: the check shows nothing";
}

// What a rating cannot mean is refused in one sentence (issue 42, point 14): curves apart in time,
// a model covering a sliver of the test (unless --start/--end ask for it), --model-units for a CSV,
// an LCID two curves share, a constant curve.
TEST_F(CorrelateCli, RatingsThatMeanNothingAreRefusedInOneSentence) {
  const std::string& test = foam_a_[0];
  const std::vector<std::string> rate = {"correlate", "--test", test, "--channel", "acc_resultant_g"};
  const auto run = [&](std::vector<std::string> more) {
    std::vector<std::string> args = rate;
    args.insert(args.end(), more.begin(), more.end());
    return Napkin(args);
  };
  test_support::WriteText(dir_->path() / "late.csv", "time_s,late_g\n1.0,0\n1.5,40\n2.0,0\n");
  const RunResult late = run({"--model", "late.csv"});
  EXPECT_EQ(late.exit_code, 1);
  test_support::ExpectOneSentenceError(late, {"runs from 1 to 2 s", "do not overlap in time"});

  std::string sliver = "time_s,sliver_g\n";
  for (int i = 0; i <= 49; ++i) sliver += util::FormatNumber(0.0001 * i) + "," + std::to_string(i % 7) + "\n";
  test_support::WriteText(dir_->path() / "sliver.csv", sliver);
  const RunResult short_model = run({"--model", "sliver.csv"});
  EXPECT_EQ(short_model.exit_code, 1);
  test_support::ExpectOneSentenceError(short_model,
                                       {"covers 4.9 %", "less than the 50 %", "--start and --end"});
  EXPECT_EQ(run({"--model", "sliver.csv", "--start", "0", "--end", "0.0049"}).exit_code, 0);

  // An LS-DYNA model read in the wrong units (its seconds taken as milliseconds): the sentence
  // gives the curve's times under those units and names them (issue 42, point 14).
  ASSERT_EQ(Napkin({"export", "--test", test, "--format", "lsdyna", "--units", "si", "--out", "model_si.k"})
                .exit_code,
            0);
  const RunResult wrong_units = run({"--model", "model_si.k:1", "--model-units", "m,ms,kg"});
  EXPECT_EQ(wrong_units.exit_code, 1);
  test_support::ExpectOneSentenceError(
      wrong_units, {"curve 'curve 1' (read in --model-units m,ms,kg) runs from 0 to", "covers"});
  EXPECT_EQ(run({"--model", "model_si.k:1", "--model-units", "m,s,kg"}).exit_code, 0) << "in its own units";

  const RunResult units = run({"--model", "sliver.csv", "--model-units", "mm,s,kg"});
  EXPECT_EQ(units.exit_code, 2);
  test_support::ExpectOneSentenceError(units, {"is a CSV, whose header gives its units"});

  // A model file is read as a stream, at most 1 GiB: a larger one is refused before it is read
  // (sparse here).
  test_support::WriteText(dir_->path() / "huge.csv", "time_s,huge_g\n");
  fs::resize_file(dir_->path() / "huge.csv", (std::uintmax_t{1} << 30) + 1);
  const RunResult huge = run({"--model", "huge.csv"});
  EXPECT_EQ(huge.exit_code, 1);
  test_support::ExpectOneSentenceError(huge, {"huge.csv", "1073741825 bytes, more than the 1024 MiB"});
  fs::remove(dir_->path() / "huge.csv");

  test_support::WriteText(dir_->path() / "unitless.csv", "time_s,head\n0,0\n0.05,40\n0.1,0\n");
  const RunResult unitless = run({"--model", "unitless.csv"});
  EXPECT_EQ(unitless.exit_code, 1);
  test_support::ExpectOneSentenceError(unitless, {"column 'head' names no unit", "(e.g. head_g)"});
  EXPECT_EQ(unitless.err.find("an angle"), std::string::npos) << unitless.err;

  test_support::WriteText(dir_->path() / "flat.csv", "time_s,flat_g\n0,0\n0.05,0\n0.1,0\n");
  const RunResult flat = run({"--model", "flat.csv"});
  EXPECT_EQ(flat.exit_code, 1);
  test_support::ExpectOneSentenceError(flat, {"flat.csv", "is constant (0 throughout)"});

  ASSERT_EQ(
      Napkin({"export", "--test", test, "--format", "lsdyna", "--units", "si", "--out", "twice.k"}).exit_code,
      0);
  const std::string keyword = test_support::ReadText(dir_->path() / "twice.k");
  const std::size_t first = keyword.find("*DEFINE_CURVE");
  const std::size_t next = keyword.find('*', first + 1);
  ASSERT_NE(next, std::string::npos);
  test_support::WriteText(
      dir_->path() / "twice.k",
      keyword.substr(0, next) + keyword.substr(first, next - first) + keyword.substr(next));
  const std::string lcid = [&] {
    std::istringstream card(keyword.substr(keyword.find('\n', first) + 1));
    std::string line;
    while (std::getline(card, line) && line.starts_with("$")) {
    }
    return std::to_string(std::stoi(line.substr(0, 10)));
  }();
  const RunResult twice = Napkin({"correlate", "--test", test, "--channel", "omega_fixed_x_radps", "--model",
                                  "twice.k:" + lcid, "--model-units", "m,s,kg"});
  EXPECT_EQ(twice.exit_code, 1) << twice.out;
  test_support::ExpectOneSentenceError(twice, {"twice.k", "curves named '" + lcid + "'", "ambiguous"});
}

// One keyword curve rated under two --model-units: two stored ratings, each saying its units
// (issue 42, point 3: the second replaced the first and neither said which units it used).
TEST_F(CorrelateCli, ModelUnitsArePartOfTheStoredRating) {
  const std::string& test = foam_a_[1];
  ASSERT_EQ(
      Napkin({"export", "--test", test, "--format", "lsdyna", "--units", "si", "--out", "units.k"}).exit_code,
      0);
  for (const char* units : {"m,s,kg", "MM, s, kg"})
    RateOne(
        {"--test", test, "--channel", "omega_fixed_x_radps", "--model", "units.k:4", "--model-units", units});
  const RunResult stored = Napkin(
      {"query", "correlation", "--where", "test_id=" + test + " and model_file=units.k", "--format", "json"});
  ASSERT_EQ(stored.exit_code, 0) << stored.err;
  const json rows = json::parse(stored.out);
  ASSERT_EQ(rows.size(), 2u) << rows.dump(2);
  std::set<std::string> units;
  for (const json& row : rows) units.insert(row.at("model_units").get<std::string>());
  EXPECT_EQ(units, (std::set<std::string>{"m,s,kg", "mm,s,kg"}));
  // A CSV model gives its own units: none stored.
  ASSERT_EQ(Napkin({"export", "--test", test, "--format", "csv", "--out", "units.csv"}).exit_code, 0);
  RateOne({"--test", test, "--channel", "acc_body_z_g", "--model", "units.csv"});
  const RunResult csv = Napkin({"query", "correlation", "--where",
                                "test_id=" + test + " and model_file=units.csv", "--format", "json"});
  ASSERT_EQ(json::parse(csv.out).size(), 1u) << csv.out;
  EXPECT_TRUE(json::parse(csv.out).at(0).at("model_units").is_null());
}

// The derived-channel CSV as the model: the column named like the channel is
// taken; a model scaled by 3 has the scores of the formulas and rates
// below 0.8, stored beside the others.
TEST_F(CorrelateCli, DerivedCsvReadBackAndScaledModelRateAsExpected) {
  const std::string& test = foam_a_[1];
  ASSERT_EQ(Napkin({"export", "--test", test, "--format", "csv", "--out", "derived.csv"}).exit_code, 0);
  // The CSV holds 12 significant digits of g: the same curve to 1e-12.
  const json same = RateOne({"--test", test, "--channel", "acc_body_x_g", "--model", "derived.csv"});
  for (const char* score : {"corridor", "phase", "magnitude", "slope", "overall"})
    EXPECT_NEAR(same.at(score).get<double>(), 1.0, 1e-9) << score;
  EXPECT_EQ(same.at("grade"), "excellent");
  EXPECT_EQ(same.at("shift_s").get<double>(), 0.0);

  // time_s and acc_body_x_g times 3.
  std::ifstream in(dir_->path() / "derived.csv");
  std::ostringstream scaled;
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = [&] {
    std::vector<std::string> names;
    std::stringstream fields(line);
    for (std::string name; std::getline(fields, name, ',');) names.push_back(name);
    return names;
  }();
  const auto column = std::find(header.begin(), header.end(), "acc_body_x_g") - header.begin();
  scaled << "time_s,model_x_g\n";
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream fields(line);
    for (std::string cell; std::getline(fields, cell, ',');) cells.push_back(cell);
    scaled << cells[0] << "," << util::FormatNumber(3.0 * std::stod(cells[static_cast<std::size_t>(column)]))
           << "\n";
  }
  test_support::WriteText(dir_->path() / "scaled.csv", scaled.str());
  const json row = RateOne({"--test", test, "--channel", "acc_body_x_g", "--model", "scaled.csv"});
  // Scaled by k = 3: the same shape, not shifted (phase 1); magnitude error
  // |k - 1| = 2 and slope error 2 reach their limits 0.5 and 2 (scores 0);
  // the corridor score is below 1 where 2|x| leaves the inner corridor.
  EXPECT_EQ(row.at("phase").get<double>(), 1.0);
  EXPECT_NEAR(row.at("magnitude").get<double>(), 0.0, 1e-9);
  EXPECT_NEAR(row.at("slope").get<double>(), 0.0, 1e-9);
  EXPECT_LT(row.at("corridor").get<double>(), 1.0);
  EXPECT_NEAR(row.at("overall").get<double>(), 0.4 * row.at("corridor").get<double>() + 0.2, 1e-12);
  EXPECT_LT(row.at("overall").get<double>(), 0.8);
  EXPECT_EQ(row.at("reference"), "scaled.csv:model_x_g");
}

// `query correlation --where "overall<0.8"` lists exactly the stored ratings
// whose overall rating is below 0.8, compared with the whole table.
TEST_F(CorrelateCli, QueryCorrelationWhereSelectsTheRows) {
  const std::string& test = foam_a_[1];
  ASSERT_EQ(Napkin({"export", "--test", test, "--format", "csv", "--out", "q.csv"}).exit_code, 0);
  test_support::WriteText(dir_->path() / "half.csv", "time_s,half_g\n0,0\n0.02,1\n0.04,0\n0.1,0\n");
  RateOne({"--test", test, "--channel", "acc_body_z_g", "--model", "q.csv"});
  RateOne({"--test", test, "--channel", "acc_body_x_g", "--model", "half.csv", "--end", "0.1"});
  RateOne({"--test", test, "--reference-test", foam_a_[0], "--channel", "acc_resultant_g"});

  const RunResult all = Napkin({"query", "correlation", "--format", "json"});
  ASSERT_EQ(all.exit_code, 0) << all.err;
  std::multiset<std::string> expected;
  std::size_t rows = 0;
  for (const json& row : json::parse(all.out)) {
    ++rows;
    ASSERT_TRUE(row.at("overall").is_number()) << row.dump();
    if (row.at("overall").get<double>() < 0.8)
      expected.insert(row.at("test_id").get<std::string>() + " " + row.at("channel").get<std::string>() +
                      " " + row.at("reference").get<std::string>());
  }
  ASSERT_GE(rows, 3u);
  ASSERT_FALSE(expected.empty());
  ASSERT_LT(expected.size(), rows);
  const RunResult low = Napkin({"query", "correlation", "--where", "overall<0.8", "--format", "json"});
  ASSERT_EQ(low.exit_code, 0) << low.err;
  std::multiset<std::string> selected;
  for (const json& row : json::parse(low.out))
    selected.insert(row.at("test_id").get<std::string>() + " " + row.at("channel").get<std::string>() + " " +
                    row.at("reference").get<std::string>());
  EXPECT_EQ(selected, expected);

  // The columns of the contract (docs/formats.md "Correlation ratings"), in order.
  const RunResult csv = Napkin({"query", "correlation", "--limit", "1", "--format", "csv"});
  ASSERT_EQ(csv.exit_code, 0) << csv.err;
  EXPECT_EQ(test_support::Lines(csv.out).front(),
            "test_id,series,variant,channel,reference_kind,reference,model_file,model_sha256,model_column,"
            "model_units,reference_test,edition,start_s,end_s,corridor,phase,magnitude,slope,overall,grade,"
            "shift_s,config,"
            "rated_at");
  // Rating again with the same reference and parameters replaces the row.
  RateOne({"--test", test, "--reference-test", foam_a_[0], "--channel", "acc_resultant_g"});
  const RunResult again = Napkin({"query", "correlation", "--format", "json"});
  EXPECT_EQ(json::parse(again.out).size(), rows);
  // A text value against a numeric field is a usage error naming it.
  const RunResult bad = Napkin({"query", "correlation", "--where", "overall=good"});
  EXPECT_EQ(bad.exit_code, 2);
}

// Each repeat against its variant's mean: every repeat rated, worst first,
// stored as 'variant-mean' ratings.
TEST_F(CorrelateCli, SeriesRatesEachRepeatAgainstTheVariantMean) {
  const RunResult run = Napkin({"correlate", "--series", "padding-series", "--variant", "foam-a", "--channel",
                                "acc_resultant_g", "--format", "json"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const json rows = json::parse(run.out);
  ASSERT_EQ(rows.size(), 2u);
  std::set<std::string> tests;
  for (const json& row : rows) {
    tests.insert(row.at("test_id").get<std::string>());
    EXPECT_EQ(row.at("reference"), "mean of foam-a");
    EXPECT_GT(row.at("overall").get<double>(), 0.0);
    EXPECT_LE(row.at("overall").get<double>(), 1.0);
  }
  EXPECT_EQ(tests, std::set<std::string>(foam_a_.begin(), foam_a_.end()));
  EXPECT_LE(rows[0].at("overall").get<double>(), rows[1].at("overall").get<double>());  // worst first
  const RunResult stored = Napkin({"query", "correlation", "--where",
                                   "reference_kind = variant-mean and variant = foam-a", "--format", "json"});
  ASSERT_EQ(stored.exit_code, 0) << stored.err;
  EXPECT_EQ(json::parse(stored.out).size(), 2u);

  const RunResult unknown = Napkin(
      {"correlate", "--series", "padding-series", "--variant", "nothing", "--channel", "acc_resultant_g"});
  EXPECT_EQ(unknown.exit_code, 1);
  test_support::ExpectOneSentenceError(unknown, {"variant 'nothing'", "padding-series"});
}

TEST_F(CorrelateCli, BadModelFilesAndOptionsAreOneSentence) {
  const std::string& test = foam_a_[0];
  test_support::WriteText(dir_->path() / "broken.csv", "time_s,head_g\n0,1\n0.001,x\n0.002,3\n");
  const RunResult broken =
      Napkin({"correlate", "--test", test, "--channel", "acc_resultant_g", "--model", "broken.csv"});
  EXPECT_EQ(broken.exit_code, 1);
  test_support::ExpectOneSentenceError(broken, {"broken.csv", "line 3"});

  const RunResult missing =
      Napkin({"correlate", "--test", test, "--channel", "acc_resultant_g", "--model", "nowhere.csv"});
  EXPECT_EQ(missing.exit_code, 1);
  test_support::ExpectOneSentenceError(missing, {"nowhere.csv", "cannot open the file"});

  test_support::WriteText(dir_->path() / "rate.csv", "time_s,head_radps\n0,1\n0.05,2\n0.1,3\n");
  const RunResult quantity =
      Napkin({"correlate", "--test", test, "--channel", "acc_resultant_g", "--model", "rate.csv"});
  EXPECT_EQ(quantity.exit_code, 1);
  test_support::ExpectOneSentenceError(quantity,
                                       {"rate.csv", "head_radps", "angular velocity", "acc_resultant_g"});

  const RunResult column =
      Napkin({"correlate", "--test", test, "--channel", "omega_body_x_radps", "--model", "rate.csv:other"});
  EXPECT_EQ(column.exit_code, 1);
  test_support::ExpectOneSentenceError(column, {"rate.csv", "'other'", "'head_radps'"});

  const RunResult channel =
      Napkin({"correlate", "--test", test, "--reference-test", test, "--channel", "hic15"});
  EXPECT_EQ(channel.exit_code, 2);
  test_support::ExpectOneSentenceError(channel, {"--channel 'hic15'", "acc_resultant_g"});

  const RunResult outside = Napkin({"correlate", "--test", test, "--reference-test", test, "--channel",
                                    "acc_resultant_g", "--start", "0.05", "--end", "5"});
  EXPECT_EQ(outside.exit_code, 1);
  test_support::ExpectOneSentenceError(outside, {"test '" + test + "' channel acc_resultant_g"});

  const RunResult forms = Napkin({"correlate", "--test", test, "--channel", "acc_resultant_g"});
  EXPECT_EQ(forms.exit_code, 2);
  test_support::ExpectOneSentenceError(forms, {"--model", "--reference-test", "--series"});

  const RunResult no_test =
      Napkin({"correlate", "--test", "nope", "--reference-test", test, "--channel", "acc_resultant_g"});
  EXPECT_EQ(no_test.exit_code, 1);
  test_support::ExpectOneSentenceError(no_test, {"test 'nope'"});
}

// `report --model FILE`: the stored ratings against that file drawn (the
// test, the model, the inner and outer corridors), the ratings table, and
// the repeatability table of each variant in the series section.
TEST_F(CorrelateCli, ReportDrawsRatingsAgainstTheModelWithCorridors) {
  const std::string& test = foam_a_[0];
  ASSERT_EQ(Napkin({"export", "--test", test, "--format", "csv", "--out", "report-model.csv"}).exit_code, 0);
  RateOne({"--test", test, "--channel", "acc_body_x_g", "--model", "report-model.csv"});
  const RunResult report =
      Napkin({"report", "--series", "padding-series", "--model", "report-model.csv", "--out", "r.html"});
  ASSERT_EQ(report.exit_code, 0) << report.err;
  const std::string html = test_support::ReadText(dir_->path() / "r.html");
  EXPECT_THAT(html, HasSubstr("ISO/TS 18571 ratings"));
  EXPECT_THAT(html,
              HasSubstr("acc_body_x_g: test against report-model.csv:acc_body_x_g, overall 1 (excellent)"));
  for (const char* label : {"inner corridor −", "inner corridor +", "outer corridor −", "outer corridor +"})
    EXPECT_THAT(html, HasSubstr(label));
  EXPECT_THAT(html, HasSubstr("\"bands\":[[2,3],[4,5]]"));
  for (const char* variant : {"foam-a", "foam-b", "production"})
    EXPECT_THAT(html, HasSubstr(std::string("Repeatability of ") + variant));

  // A model file no stored rating names: one sentence naming it.
  test_support::WriteText(dir_->path() / "unrated.csv", "time_s,x_g\n0,1\n0.1,2\n");
  const RunResult unrated =
      Napkin({"report", "--series", "padding-series", "--model", "unrated.csv", "--out", "u.html"});
  EXPECT_EQ(unrated.exit_code, 1);
  test_support::ExpectOneSentenceError(unrated, {"model file 'unrated.csv'", "napkin correlate"});

  // An LS-DYNA model without --model-units is refused before the page is
  // begun: nothing on standard output, no file.
  ASSERT_EQ(
      Napkin({"export", "--test", test, "--format", "lsdyna", "--units", "si", "--out", "report-head.k"})
          .exit_code,
      0);
  for (const std::string out : {"-", "k.html"}) {
    const RunResult unitless =
        Napkin({"report", "--series", "padding-series", "--model", "report-head.k", "--out", out});
    EXPECT_EQ(unitless.exit_code, 2) << out;
    EXPECT_EQ(unitless.out, "") << out;
    test_support::ExpectOneSentenceError(unitless, {"model file 'report-head.k'", "--model-units"});
  }
  EXPECT_FALSE(std::filesystem::exists(dir_->path() / "k.html"));
}

}  // namespace
}  // namespace napkin
