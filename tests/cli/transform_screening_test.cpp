// `napkin transform --summary` end to end (issue 3): the summary carries HIC,
// BrIC, DAMAGE and the screening findings (`quality`) of the input file; an
// error-severity finding fails the file as `napkin run` fails it (issue 8).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "engine/criteria.h"
#include "engine/units.h"
#include "formats/csv.h"
#include "synth/synthetic_tests.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/reference_arrays.h"
#include "tests/support/run_command.h"
#include "tests/support/test_support.h"

namespace napkin {
namespace {

using test_support::ReadText;

// Runs `napkin transform` on `input` with the test's initial state.
test_support::CommandResult Transform(const test_support::TempDir& dir, const synth::SyntheticTest& test,
                                      const std::string& input, const std::string& array = "denton-3222") {
  return test_support::RunProgram(
      NAPKIN_BINARY,
      {"transform", "--array", array, test_support::TripleFlag("--orientation", test.initial.orientation_rad),
       test_support::TripleFlag("--initial-velocity", test.initial.velocity_fixed_mps), "--out",
       (dir / "out.csv").string(), "--summary", (dir / "s.json").string(), input});
}

double TrueHic15(const synth::SyntheticTest& test) {
  const Eigen::VectorXd acc_g = test.truth.acc_fixed.rowwise().norm() / engine::kStandardGravity;
  engine::HicOptions window;
  window.window_s = engine::kHic15Window;
  return engine::Hic(acc_g, test.signals.dt_s, test.signals.t0_s, window).value;
}

synth::SyntheticTest Motion() {
  synth::RandomMotionOptions options;
  options.seed = 3;
  return synth::SynthRandomMotion(test_support::Denton3222(), options);
}

// Motion() from rest at the initial orientation: the salvage tests compare
// against its truth.
synth::SyntheticTest RestingMotion() {
  synth::RandomMotionOptions options;
  options.seed = 3;
  options.random_initial_orientation = false;
  options.random_initial_velocity = false;
  return synth::SynthRandomMotion(test_support::Denton3222(), options);
}

TEST(TransformScreening, CleanFileSummaryHasCriteriaAndNoFindingAboveInfo) {
  test_support::TempDir dir;
  const synth::SyntheticTest test = Motion();
  formats::WriteSignalsCsv(test.signals, dir / "clean.csv");
  const test_support::CommandResult run = Transform(dir, test, (dir / "clean.csv").string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json summary = nlohmann::json::parse(ReadText(dir / "s.json"));
  EXPECT_NEAR(summary.at("hic15").get<double>(), TrueHic15(test), 0.001 * TrueHic15(test));
  EXPECT_GT(summary.at("bric").get<double>(), 0.0);
  EXPECT_GT(summary.at("damage").get<double>(), 0.0);
  ASSERT_TRUE(summary.at("quality").is_array());
  for (const auto& finding : summary.at("quality"))
    EXPECT_EQ(finding.at("severity"), "info") << finding.dump();
  EXPECT_TRUE(std::filesystem::exists(dir / "out.csv"));
}

// A spike the rigid body pins on one channel is a faulty channel (issue 41):
// exit 1 naming it, and the sentence says what salvage would do.
TEST(TransformScreening, SpikedChannelFailsNamingItAndSalvage) {
  test_support::TempDir dir;
  synth::SyntheticTest test = Motion();
  auto spiked = test.signals.samples.col(test.signals.FindSlot("xarm_y"));
  spiked(700) += 120.0;  // g
  formats::WriteSignalsCsv(test.signals, dir / "spiked.csv");
  const test_support::CommandResult run = Transform(dir, test, (dir / "spiked.csv").string());
  EXPECT_EQ(run.exit_code, 1) << run.err;
  test_support::ExpectOneSentenceError(run, {"spiked.csv: ", "xarm_y", "--config salvage"});
  EXPECT_FALSE(std::filesystem::exists(dir / "s.json"));
}

// An error-severity finding fails the test in `napkin transform` as in
// `napkin run` (engine::FailingFinding): exit 1, the finding's sentence
// naming the file and the channel, no output.
TEST(TransformScreening, ClippedChannelFailsNamingItAndWritesNothing) {
  test_support::TempDir dir;
  synth::SyntheticTest test = Motion();
  auto spiked = test.signals.samples.col(test.signals.FindSlot("xarm_y"));
  spiked(700) += 120.0;  // g
  auto clipped = test.signals.samples.col(test.signals.FindSlot("cg_z"));
  const double clip = 0.8 * clipped.cwiseAbs().maxCoeff();
  clipped = clipped.cwiseMax(-clip).cwiseMin(clip);
  formats::WriteSignalsCsv(test.signals, dir / "faulty.csv");
  const test_support::CommandResult run = Transform(dir, test, (dir / "faulty.csv").string());
  EXPECT_EQ(run.exit_code, 1);
  test_support::ExpectOneSentenceError(run, {"faulty.csv: ", "cg_z", "saturat"});
  EXPECT_FALSE(std::filesystem::exists(dir / "s.json"));
  EXPECT_FALSE(std::filesystem::exists(dir / "out.csv"));
}

TEST(TransformScreening, FlippedChannelThatBreaksTheSolveFailsNamingIt) {
  test_support::TempDir dir;
  synth::SyntheticTest test = Motion();
  test.signals.samples.col(test.signals.FindSlot("zarm_x")) *= -1.0;
  formats::WriteSignalsCsv(test.signals, dir / "flipped.csv");
  const test_support::CommandResult run = Transform(dir, test, (dir / "flipped.csv").string());
  // The linear-only solve of this motion diverges with zarm_x flipped: no
  // result, exit 1, the reason names the channel, nothing is written.
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("flipped.csv"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("diverge"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("zarm_x appears sign flipped"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "s.json"));
  EXPECT_FALSE(std::filesystem::exists(dir / "out.csv"));
}

// With angular-rate sensors omega is measured, not integrated: a flipped
// linear channel leaves the solve finite, but its polarity error fails the
// test all the same (as `napkin run` fails it): exit 1, nothing written.
TEST(TransformScreening, FlippedChannelFailsNamingItAndWritesNothing) {
  test_support::TempDir dir;
  synth::RandomMotionOptions options;
  options.seed = 3;
  synth::SyntheticTest test = synth::SynthRandomMotion(test_support::NapArs12(), options);
  test.signals.samples.col(test.signals.FindSlot("yarm_z")) *= -1.0;
  formats::WriteSignalsCsv(test.signals, dir / "flipped.csv");
  const test_support::CommandResult run = Transform(dir, test, (dir / "flipped.csv").string(), "nap-ars-12");
  EXPECT_EQ(run.exit_code, 1);
  test_support::ExpectOneSentenceError(run, {"flipped.csv: ", "yarm_z appears sign flipped"});
  EXPECT_EQ(run.err.find("diverge"), std::string::npos) << "the solve is finite: " << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "s.json"));
  EXPECT_FALSE(std::filesystem::exists(dir / "out.csv"));
}

// `napkin run` and `napkin transform` reach one verdict on the same file: the
// failure run records is, word for word, the sentence transform exits with
// (after the file name); a clean file passes both.
TEST(TransformScreening, RunAndTransformAgreeOnTheSameFiles) {
  test_support::TempDir dir;
  synth::RandomMotionOptions options;
  options.seed = 3;
  const synth::SyntheticTest clean = synth::SynthRandomMotion(test_support::NapArs12(), options);
  synth::SyntheticTest flipped = clean;
  flipped.signals.samples.col(flipped.signals.FindSlot("yarm_z")) *= -1.0;
  std::filesystem::create_directories(dir / "tests");
  formats::WriteSignalsCsv(clean.signals, dir / "tests" / "clean.csv");
  formats::WriteSignalsCsv(flipped.signals, dir / "tests" / "flipped.csv");

  const std::string db = (dir / "verdict.db").string();
  const test_support::CommandResult import = test_support::RunNapkin(
      dir.path(), {"--db", db, "import", "--array", "nap-ars-12", "--series", "verdict",
                   test_support::TripleFlag("--orientation", clean.initial.orientation_rad),
                   test_support::TripleFlag("--initial-velocity", clean.initial.velocity_fixed_mps),
                   (dir / "tests").string()});
  ASSERT_EQ(import.exit_code, 0) << import.err;
  const test_support::CommandResult run = test_support::RunNapkin(dir.path(), {"--db", db, "run"});
  EXPECT_EQ(run.exit_code, 3) << run.err;  // partial success: one test failed
  const test_support::CommandResult status =
      test_support::RunNapkin(dir.path(), {"--db", db, "status", "--format", "json"});
  ASSERT_EQ(status.exit_code, 0) << status.err;
  const nlohmann::json counts = nlohmann::json::parse(status.out);
  EXPECT_EQ(counts.at("done"), 1) << status.out;
  ASSERT_EQ(counts.at("failures").size(), 1u) << status.out;
  EXPECT_EQ(counts.at("failures")[0].at("test_id"), "flipped") << status.out;
  const std::string stored = counts.at("failures")[0].at("error").get<std::string>();
  EXPECT_NE(stored.find("yarm_z appears sign flipped"), std::string::npos) << stored;

  const std::string flipped_csv = (dir / "tests" / "flipped.csv").string();
  const test_support::CommandResult failed = Transform(dir, flipped, flipped_csv, "nap-ars-12");
  EXPECT_EQ(failed.exit_code, 1);
  EXPECT_EQ(failed.err, "napkin: " + flipped_csv + ": " + stored + "\n");
  EXPECT_FALSE(std::filesystem::exists(dir / "s.json"));
  EXPECT_FALSE(std::filesystem::exists(dir / "out.csv"));

  const test_support::CommandResult passed =
      Transform(dir, clean, (dir / "tests" / "clean.csv").string(), "nap-ars-12");
  EXPECT_EQ(passed.exit_code, 0) << passed.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "s.json"));
  EXPECT_TRUE(std::filesystem::exists(dir / "out.csv"));
}

TEST(TransformScreening, NanInTheFileFailsNamingRowAndColumn) {
  test_support::TempDir dir;
  const synth::SyntheticTest test = Motion();
  formats::WriteSignalsCsv(test.signals, dir / "clean.csv");
  // Replace the yarm_x value of one data row by "nan".
  std::istringstream lines(ReadText(dir / "clean.csv"));
  std::ofstream out(dir / "dropout.csv");
  std::string line, header;
  int data_row = 0, yarm_x_column = -1;
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] == '#') {
      out << line << "\n";
      continue;
    }
    std::vector<std::string> cells;
    std::stringstream cell_stream(line);
    for (std::string cell; std::getline(cell_stream, cell, ',');) cells.push_back(cell);
    if (header.empty()) {
      header = line;
      for (std::size_t c = 0; c < cells.size(); ++c)
        if (cells[c] == "yarm_x") yarm_x_column = static_cast<int>(c);
    } else if (++data_row == 500) {
      cells[static_cast<std::size_t>(yarm_x_column)] = "nan";
    }
    for (std::size_t c = 0; c < cells.size(); ++c) out << (c ? "," : "") << cells[c];
    out << "\n";
  }
  out.close();
  ASSERT_GE(yarm_x_column, 0);
  const test_support::CommandResult run = Transform(dir, test, (dir / "dropout.csv").string());
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("dropout.csv"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("yarm_x"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("row"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "s.json"));
}

// Issue 41: `--config salvage` repairs the spiked channel and every front
// end says so: the summary's record, the catalogue's `salvaged` column,
// `status`, and the report's badge.
TEST(TransformScreening, SalvageRepairsTheSpikedChannelAndEveryFrontEndSaysSo) {
  test_support::TempDir dir;
  synth::SyntheticTest test = RestingMotion();
  std::filesystem::create_directories(dir / "in");
  formats::WriteSignalsCsv(test.signals, dir / "in" / "clean.csv");
  test.signals.samples.col(test.signals.FindSlot("xarm_y"))(700) += 120.0;  // g
  formats::WriteSignalsCsv(test.signals, dir / "in" / "spiked.csv");

  const test_support::CommandResult transform = test_support::RunProgram(
      NAPKIN_BINARY,
      {"transform", "--array", "denton-3222", "--config", "salvage", "--out", (dir / "out.csv").string(),
       "--summary", (dir / "s.json").string(), (dir / "in" / "spiked.csv").string()});
  ASSERT_EQ(transform.exit_code, 0) << transform.err;
  const nlohmann::json summary = nlohmann::json::parse(ReadText(dir / "s.json"));
  const nlohmann::json& salvage = summary.at("salvage");
  EXPECT_EQ(salvage.at("mode"), "repair");
  ASSERT_EQ(salvage.at("channels").size(), 1u) << salvage.dump();
  EXPECT_EQ(salvage.at("channels")[0].at("channel"), "xarm_y");
  EXPECT_EQ(salvage.at("channels")[0].at("action"), "replaced");
  EXPECT_GE(salvage.at("channels")[0].at("samples_replaced").get<int>(), 1);
  EXPECT_LT(salvage.at("rms_residual_after_g").get<double>(),
            0.1 * salvage.at("rms_residual_before_g").get<double>());
  EXPECT_NEAR(summary.at("hic15").get<double>(), TrueHic15(test), 0.01 * TrueHic15(test));

  const std::string db = (dir / "c.db").string();
  const auto napkin = [&](std::vector<std::string> args) {
    args.insert(args.begin(), {"--db", db});
    return test_support::RunProgram(NAPKIN_BINARY, args);
  };
  ASSERT_EQ(
      napkin({"import", "--array", "denton-3222", "--series", "s", "--variant", "v", (dir / "in").string()})
          .exit_code,
      0);
  const test_support::CommandResult run = napkin({"run", "--config", "salvage"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const test_support::CommandResult salvaged =
      napkin({"query", "tests", "--where", "salvaged=1", "--format", "json"});
  ASSERT_EQ(salvaged.exit_code, 0) << salvaged.err;
  const nlohmann::json rows = nlohmann::json::parse(salvaged.out);
  ASSERT_EQ(rows.size(), 1u) << salvaged.out;
  EXPECT_EQ(rows[0].at("test_id"), "spiked");
  const test_support::CommandResult criteria =
      napkin({"query", "criteria", "--where", "salvaged=0", "--format", "json"});
  ASSERT_EQ(criteria.exit_code, 0) << criteria.err;
  ASSERT_EQ(nlohmann::json::parse(criteria.out).size(), 1u) << criteria.out;
  EXPECT_EQ(nlohmann::json::parse(criteria.out)[0].at("test_id"), "clean");
  const test_support::CommandResult status = napkin({"status", "--config", "salvage", "--format", "json"});
  ASSERT_EQ(status.exit_code, 0) << status.err;
  EXPECT_EQ(nlohmann::json::parse(status.out).at("salvaged"), 1);
  const test_support::CommandResult report = napkin({"report", "--out", (dir / "r.html").string()});
  ASSERT_EQ(report.exit_code, 0) << report.err;
  const std::string html = ReadText(dir / "r.html");
  std::size_t badges = 0;
  for (std::size_t at = html.find("class=\"badge salvaged\""); at != std::string::npos;
       at = html.find("class=\"badge salvaged\"", at + 1))
    ++badges;
  EXPECT_EQ(badges, 1u);
  EXPECT_NE(html.find("salvaged (repair: xarm_y replaced)"), std::string::npos);
}

// Issue 41, point 2: the repaired raw channel is kept beside the recorded
// one and can be exported. `export --format channels` writes the channels the
// salvaged result was computed from: every sample the recorded one but the
// repaired ones, and transforming that file with the default config gives
// the salvaged result; `--format recorded` gives the spike back; the report
// overlays the two.
TEST(TransformScreening, TheRepairedChannelIsKeptExportedAndOverlaid) {
  test_support::TempDir dir;
  synth::SyntheticTest test = RestingMotion();
  const engine::TestSignals clean = test.signals;
  const int column = test.signals.FindSlot("xarm_y");
  test.signals.samples.col(column)(700) += 120.0;  // g
  std::filesystem::create_directories(dir / "in");
  formats::WriteSignalsCsv(test.signals, dir / "in" / "spiked.csv");
  const std::string db = (dir / "c.db").string();
  const auto napkin = [&](std::vector<std::string> args) {
    args.insert(args.begin(), {"--db", db});
    return test_support::RunProgram(NAPKIN_BINARY, args);
  };
  ASSERT_EQ(napkin({"import", "--array", "denton-3222", (dir / "in").string()}).exit_code, 0);
  // The recorded channels need no result.
  const std::string before_csv = (dir / "before.csv").string();
  const test_support::CommandResult before =
      napkin({"export", "--test", "spiked", "--format", "recorded", "--out", before_csv});
  ASSERT_EQ(before.exit_code, 0) << before.err;
  EXPECT_EQ(formats::ReadSignalsCsv(before_csv, &test.array).signals.samples, test.signals.samples);
  const test_support::CommandResult run = napkin({"run", "--config", "salvage"});
  ASSERT_EQ(run.exit_code, 0) << run.err;

  const std::string channels_csv = (dir / "channels.csv").string();
  const test_support::CommandResult exported =
      napkin({"export", "--test", "spiked", "--format", "channels", "--out", channels_csv});
  ASSERT_EQ(exported.exit_code, 0) << exported.err;
  const std::string text = ReadText(channels_csv);
  EXPECT_NE(text.find("# xarm_y: repaired by salvage (spike"), std::string::npos) << text.substr(0, 600);
  EXPECT_NE(text.find("# array: denton-3222"), std::string::npos) << text.substr(0, 600);
  const engine::TestSignals repaired = formats::ReadSignalsCsv(channels_csv, &test.array).signals;
  ASSERT_EQ(repaired.slots, test.signals.slots);
  ASSERT_EQ(repaired.size(), test.signals.size());
  Eigen::Index changed = 0;
  for (Eigen::Index c = 0; c < repaired.samples.cols(); ++c)
    for (Eigen::Index k = 0; k < repaired.size(); ++k)
      if (repaired.samples(k, c) != test.signals.samples(k, c)) {
        ++changed;
        EXPECT_EQ(c, column) << "sample " << k << " of " << repaired.slots[static_cast<std::size_t>(c)];
      }
  EXPECT_GE(changed, 1);
  // The spike's sample is the rigid-body prediction: near the clean value.
  EXPECT_NEAR(repaired.samples(700, column), clean.samples(700, column), 0.5);

  // Transformed with the default config, the exported channels give the salvaged result.
  const test_support::CommandResult transform = test_support::RunProgram(
      NAPKIN_BINARY, {"transform", "--array", "denton-3222", "--out", (dir / "k.csv").string(), "--summary",
                      (dir / "s.json").string(), channels_csv});
  ASSERT_EQ(transform.exit_code, 0) << transform.err;
  const test_support::CommandResult criteria = napkin({"query", "criteria", "--format", "json"});
  ASSERT_EQ(criteria.exit_code, 0) << criteria.err;
  const nlohmann::json salvaged = nlohmann::json::parse(criteria.out).at(0);
  const nlohmann::json again = nlohmann::json::parse(ReadText(dir / "s.json"));
  for (const char* field : {"hic15", "peak_omega_radps", "a3ms_g"})
    EXPECT_NEAR(again.at(field).get<double>(), salvaged.at(field).get<double>(),
                1e-9 * std::abs(salvaged.at(field).get<double>()))
        << field;

  const std::string recorded_csv = (dir / "recorded.csv").string();
  ASSERT_EQ(napkin({"export", "--test", "spiked", "--format", "recorded", "--out", recorded_csv}).exit_code,
            0);
  const engine::TestSignals recorded = formats::ReadSignalsCsv(recorded_csv, &test.array).signals;
  EXPECT_EQ(recorded.samples, test.signals.samples);
  EXPECT_NE(ReadText(recorded_csv).find("# xarm_y: as recorded; salvage (repair) replaced it (spike"),
            std::string::npos);

  ASSERT_EQ(napkin({"report", "--out", (dir / "r.html").string()}).exit_code, 0);
  const std::string html = ReadText(dir / "r.html");
  EXPECT_NE(html.find("xarm_y: recorded and repaired (salvage)"), std::string::npos);
  EXPECT_NE(html.find("\"id\":\"chart-1-salvage-1\""), std::string::npos);
}

}  // namespace
}  // namespace napkin
