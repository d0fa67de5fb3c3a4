// `napkin transform --summary` end to end (issue 3): the summary carries HIC,
// BrIC, DAMAGE and the screening findings (`quality`) of the input file.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "engine/criteria.h"
#include "engine/synth.h"
#include "engine/units.h"
#include "formats/csv.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/reference_arrays.h"
#include "tests/support/run_command.h"
#include "tests/support/test_support.h"

namespace napkin {
namespace {

using testing::ReadText;

// Runs `napkin transform` on `input` with the test's initial state.
testing::CommandResult Transform(const testing::TempDir& dir, const engine::SyntheticTest& test,
                                 const std::string& input, const std::string& array = "denton-3222") {
  return testing::RunProgram(
      NAPKIN_BINARY, {"transform", "--array", array, cli::test::TripleFlag("--orientation", test.initial.orientation_rad),
                      cli::test::TripleFlag("--initial-velocity", test.initial.velocity_fixed_mps), "--out",
                      (dir / "out.csv").string(), "--summary", (dir / "s.json").string(), input});
}

double TrueHic15(const engine::SyntheticTest& test) {
  const Eigen::VectorXd acc_g = test.truth.acc_fixed.rowwise().norm() / engine::kStandardGravity;
  engine::HicOptions window;
  window.window_s = engine::kHic15Window;
  return engine::Hic(acc_g, test.signals.dt_s, test.signals.t0_s, window).value;
}

engine::SyntheticTest Motion() {
  engine::RandomMotionOptions options;
  options.seed = 3;
  return engine::SynthRandomMotion(testing::Denton3222(), options);
}

TEST(TransformScreening, CleanFileSummaryHasCriteriaAndNoFindingAboveInfo) {
  testing::TempDir dir;
  const engine::SyntheticTest test = Motion();
  formats::WriteSignalsCsv(test.signals, dir / "clean.csv");
  const testing::CommandResult run = Transform(dir, test, (dir / "clean.csv").string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json summary = nlohmann::json::parse(ReadText(dir / "s.json"));
  EXPECT_NEAR(summary.at("hic15").get<double>(), TrueHic15(test), 0.001 * TrueHic15(test));
  EXPECT_GT(summary.at("bric").get<double>(), 0.0);
  EXPECT_GT(summary.at("damage").get<double>(), 0.0);
  ASSERT_TRUE(summary.at("quality").is_array());
  for (const auto& finding : summary.at("quality")) EXPECT_EQ(finding.at("severity"), "info") << finding.dump();
  EXPECT_TRUE(std::filesystem::exists(dir / "out.csv"));
}

TEST(TransformScreening, SummaryNamesTheSpikedAndTheClippedChannel) {
  testing::TempDir dir;
  engine::SyntheticTest test = Motion();
  const engine::SyntheticTest clean = test;
  auto spiked = test.signals.samples.col(test.signals.FindSlot("xarm_y"));
  spiked(700) += 120.0;  // g
  auto clipped = test.signals.samples.col(test.signals.FindSlot("cg_z"));
  const double clip = 0.8 * clipped.cwiseAbs().maxCoeff();
  clipped = clipped.cwiseMax(-clip).cwiseMin(clip);
  formats::WriteSignalsCsv(test.signals, dir / "faulty.csv");
  const testing::CommandResult run = Transform(dir, test, (dir / "faulty.csv").string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json summary = nlohmann::json::parse(ReadText(dir / "s.json"));
  for (const char* key : {"hic15", "hic15_t1_s", "bric", "damage", "peak_omega_radps"})
    EXPECT_TRUE(summary.at(key).is_number()) << key;
  bool spike = false, saturation = false;
  for (const auto& finding : summary.at("quality")) {
    if (finding.at("check") == "spike") {
      EXPECT_EQ(finding.at("channel"), "xarm_y") << finding.dump();
      EXPECT_EQ(finding.at("severity"), "warning");
      EXPECT_NE(finding.at("detail").get<std::string>().find("sample 700 "), std::string::npos) << finding.dump();
      spike = true;
    }
    if (finding.at("check") == "saturation") {
      EXPECT_EQ(finding.at("channel"), "cg_z") << finding.dump();
      EXPECT_EQ(finding.at("severity"), "error");
      saturation = true;
    }
  }
  EXPECT_TRUE(spike) << summary.at("quality").dump(2);
  EXPECT_TRUE(saturation) << summary.at("quality").dump(2);
  // The clipped channel is still processed: the HIC15 moves off the truth.
  EXPECT_NE(summary.at("hic15").get<double>(), TrueHic15(clean));
}

TEST(TransformScreening, FlippedChannelThatBreaksTheSolveFailsNamingIt) {
  testing::TempDir dir;
  engine::SyntheticTest test = Motion();
  test.signals.samples.col(test.signals.FindSlot("zarm_x")) *= -1.0;
  formats::WriteSignalsCsv(test.signals, dir / "flipped.csv");
  const testing::CommandResult run = Transform(dir, test, (dir / "flipped.csv").string());
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
// linear channel leaves the solve finite; it is processed and flagged.
TEST(TransformScreening, FlippedChannelIsFlaggedInTheSummary) {
  testing::TempDir dir;
  engine::RandomMotionOptions options;
  options.seed = 3;
  engine::SyntheticTest test = engine::SynthRandomMotion(testing::NapArs12(), options);
  test.signals.samples.col(test.signals.FindSlot("yarm_z")) *= -1.0;
  formats::WriteSignalsCsv(test.signals, dir / "flipped.csv");
  const testing::CommandResult run = Transform(dir, test, (dir / "flipped.csv").string(), "nap-ars-12");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json summary = nlohmann::json::parse(ReadText(dir / "s.json"));
  EXPECT_TRUE(summary.at("hic15").is_number());
  int polarity = 0;
  for (const auto& finding : summary.at("quality")) {
    if (finding.at("check") != "polarity") continue;
    EXPECT_EQ(finding.at("channel"), "yarm_z") << finding.dump();
    EXPECT_EQ(finding.at("severity"), "error");
    ++polarity;
  }
  EXPECT_EQ(polarity, 1) << summary.at("quality").dump(2);
}

TEST(TransformScreening, NanInTheFileFailsNamingRowAndColumn) {
  testing::TempDir dir;
  const engine::SyntheticTest test = Motion();
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
  const testing::CommandResult run = Transform(dir, test, (dir / "dropout.csv").string());
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("dropout.csv"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("yarm_x"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("row"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "s.json"));
}

}  // namespace
}  // namespace napkin
