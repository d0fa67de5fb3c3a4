// `napkin transform` end to end: the binary on files, exit codes, one-sentence
// errors, no partial output (issue 2 acceptance).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "common/error.h"
#include "engine/report_known_answers.h"
#include "formats/csv.h"
#include "synth/synthetic_tests.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/reference_arrays.h"
#include "tests/support/run_command.h"
#include "tests/support/test_support.h"

namespace napkin::test_support {
namespace {

namespace fs = std::filesystem;

class TransformCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const synth::SyntheticTest test = synth::SynthSeedFixedAxis(Denton3222(), Eigen::Vector3d(0.5, 0.5, 0.5));
    input_ = dir_ / "t1.csv";
    formats::WriteSignalsCsv(test.signals, input_);
    csv_text_ = ReadText(input_);
  }

  CommandResult Transform(const fs::path& input, const std::string& array = "denton-3222") {
    return RunProgram(NAPKIN_BINARY,
                      {"transform", "--array", array, "--orientation", "0.5,0.5,0.5", input.string(), "--out",
                       (dir_ / "out.csv").string(), "--summary", (dir_ / "out.json").string()},
                      dir_.path());
  }

  // Bad input: exit 1, one sentence naming `expected` on stderr, no output files.
  void ExpectRefused(const CommandResult& result, const std::string& expected) {
    EXPECT_EQ(result.exit_code, 1) << result.err;
    EXPECT_NE(result.err.find(expected), std::string::npos) << result.err;
    EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
    EXPECT_TRUE(result.err.ends_with(".\n")) << result.err;
    EXPECT_FALSE(fs::exists(dir_ / "out.csv"));
    EXPECT_FALSE(fs::exists(dir_ / "out.json"));
    for (const auto& entry : fs::directory_iterator(dir_.path()))
      EXPECT_EQ(entry.path().filename().string().find("out."), std::string::npos)
          << "leftover " << entry.path();
  }

  // The CSV with line `line` (0-based, header = 0) replaced by `f(line)`.
  fs::path Edited(const std::string& name, int line_number,
                  const std::function<std::string(const std::string&)>& edit) {
    std::istringstream in(csv_text_);
    std::string line, out;
    for (int i = 0; std::getline(in, line); ++i) out += (i == line_number ? edit(line) : line) + "\n";
    fs::path path = dir_ / name;
    WriteText(path, out);
    return path;
  }

  TempDir dir_;
  fs::path input_;
  std::string csv_text_;
};

TEST_F(TransformCliTest, WritesTheDerivedChannelContractAndSummary) {
  const CommandResult result = Transform(input_);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  std::istringstream csv(ReadText(dir_ / "out.csv"));
  std::string header;
  std::getline(csv, header);
  std::string expected_header;
  for (const auto& column : formats::DerivedCsvColumns())
    expected_header += (expected_header.empty() ? "" : ",") + column;
  EXPECT_EQ(header, expected_header);
  EXPECT_EQ(header.substr(0, 27), "time_s,omega_body_x_radps,o");
  int rows = 0;
  double peak_omega_fixed_y = 0;
  for (std::string row; std::getline(csv, row); ++rows) {
    std::istringstream fields(row);
    std::string field;
    for (int column = 0; std::getline(fields, field, ','); ++column)
      if (column == 8) peak_omega_fixed_y = std::max(peak_omega_fixed_y, std::stod(field));
  }
  EXPECT_EQ(rows, 1001);  // 0..100 ms at 10 kHz
  EXPECT_NEAR(peak_omega_fixed_y, engine::report::kPeakOmegaFixedYRadps,
              engine::report::kPeakOmegaFixedYRadps * 5e-5);

  const nlohmann::json summary = nlohmann::json::parse(ReadText(dir_ / "out.json"));
  EXPECT_EQ(summary["test_id"], "t1");
  EXPECT_NEAR(summary["hic"].get<double>(), engine::report::kHic, 0.01);
  EXPECT_NEAR(summary["hic_t1_s"].get<double>(), engine::report::kHicT1S, 1e-4 + 1e-9);
  EXPECT_NEAR(summary["hic_t2_s"].get<double>(), engine::report::kHicT2S, 1e-4 + 1e-9);
  EXPECT_NEAR(summary["hic36"].get<double>(), engine::report::kHic36, 0.01);
  EXPECT_NEAR(summary["hic15"].get<double>(), engine::report::kHic15, 0.01);
  // FMVSS 201 HIC(d) from the stored HIC36, exactly the engine's arithmetic.
  EXPECT_EQ(summary["hic_d"].get<double>(), 0.75446 * summary["hic36"].get<double>() + 166.4);
  EXPECT_NEAR(summary["peak_acc_g"].get<double>(), engine::report::kPeakAccG, 0.005);
  for (const char* field : {"peak_omega_radps", "peak_alpha_radps2", "bric", "damage", "final_quat_w",
                            "final_roll_deg", "final_pos_x_m", "max_rotation_deg", "a3ms_g"})
    EXPECT_TRUE(summary.contains(field)) << field;
  EXPECT_TRUE(summary["quality"].is_array());
  EXPECT_NEAR(summary["max_rotation_deg"].get<double>(), engine::report::kTotalRotationDeg, 0.005);
}

TEST_F(TransformCliTest, SeedSolverRunsThroughTheSameCommand) {
  const CommandResult result =
      RunProgram(NAPKIN_BINARY, {"transform", "--array", "denton-3222", "--solver", "seed", "--orientation",
                                 "0.5,0.5,0.5", input_.string(), "--out", (dir_ / "seed.csv").string()});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_TRUE(fs::exists(dir_ / "seed.csv"));
}

// An unknown solver name is an error, never the exact solver (issue 8).
TEST_F(TransformCliTest, UnknownSolverIsRefusedNotTakenForExact) {
  const CommandResult usage =
      RunProgram(NAPKIN_BINARY, {"transform", "--array", "denton-3222", "--solver", "fast", "--orientation",
                                 "0.5,0.5,0.5", input_.string(), "--out", (dir_ / "fast.csv").string()});
  EXPECT_EQ(usage.exit_code, 2) << usage.err;
  EXPECT_NE(usage.err.find("fast"), std::string::npos) << usage.err;
  EXPECT_FALSE(fs::exists(dir_ / "fast.csv"));
}

TEST_F(TransformCliTest, MissingColumnIsRefused) {
  // Drop the cg_y column (third field) from every line.
  std::istringstream in(csv_text_);
  std::string line, out;
  while (std::getline(in, line)) {
    if (line.starts_with("#")) {
      out += line + "\n";
      continue;
    }
    std::vector<std::string> fields;
    std::istringstream split(line);
    for (std::string field; std::getline(split, field, ',');) fields.push_back(field);
    std::string kept;
    for (std::size_t i = 0; i < fields.size(); ++i)
      if (i != 2) kept += (kept.empty() ? "" : ",") + fields[i];
    out += kept + "\n";
  }
  ASSERT_NE(csv_text_.find("cg_y"), std::string::npos);
  WriteText(dir_ / "missing.csv", out);
  ExpectRefused(Transform(dir_ / "missing.csv"), "cg_y");
}

TEST_F(TransformCliTest, NonUniformTimeIsRefusedNamingTheRow) {
  const fs::path path = Edited("jitter.csv", 500, [](const std::string& line) {
    std::string edited = "0.0499123";
    edited.append(line, line.find(','));
    return edited;
  });
  ExpectRefused(Transform(path), "jitter.csv");
}

TEST_F(TransformCliTest, NanIsRefusedNamingRowAndColumn) {
  const fs::path path = Edited("nan.csv", 300, [](const std::string& line) {
    const auto first = line.find(',');
    const auto second = line.find(',', first + 1);
    std::string edited(line, 0, first + 1);
    edited.append("nan");
    edited.append(line, second);
    return edited;
  });
  ExpectRefused(Transform(path), "cg_x");
}

// A name that is neither a file nor a preset: exit 2 and one sentence of one
// shape for every kind of preset, listing the kind's presets (each a file of
// its folder), and no output (docs/formats.md "Presets").
TEST_F(TransformCliTest, AnUnknownPresetOfEveryKindIsOneUsageSentence) {
  const std::vector<std::string> transform = {"transform", input_.string(), "--out",
                                              (dir_ / "out.csv").string()};
  const auto with = [&](std::vector<std::string> options) {
    options.insert(options.begin(), transform.begin(), transform.end());
    return options;
  };
  const fs::path db = dir_ / "c.db";
  ASSERT_EQ(RunProgram(NAPKIN_BINARY, {"--db", db.string(), "init"}, dir_.path()).exit_code, 0);
  const struct {
    std::vector<std::string> args;
    std::string folder;
    std::string a_preset;
  } cases[] = {
      {with({"--array", "nope"}), "arrays", "denton-3222"},
      {with({"--array", "denton-3222", "--config", "nope"}), "processing", "default"},
      {with({"--array", "denton-3222", "--channel-map", "nope"}), "channel-maps", "default"},
      {{"--db", db.string(), "query", "limits", "--limits", "nope"}, "limits", "fmvss208"},
  };
  const std::regex sentence(R"(napkin: "nope" is neither a file nor a preset in (.+) \(presets: (.+)\)\.\n)");
  for (const auto& c : cases) {
    SCOPED_TRACE(c.folder);
    const CommandResult result = RunProgram(NAPKIN_BINARY, c.args, dir_.path());
    EXPECT_EQ(result.exit_code, 2) << result.err;
    EXPECT_EQ(result.out, "");
    std::smatch match;
    ASSERT_TRUE(std::regex_match(result.err, match, sentence)) << result.err;
    const fs::path folder(match[1].str());
    EXPECT_EQ(folder.filename(), c.folder);
    std::vector<std::string> listed;
    std::istringstream names(match[2].str());
    for (std::string name; std::getline(names, name, ',');)
      listed.push_back(name.substr(name.front() == ' '));
    EXPECT_NE(std::find(listed.begin(), listed.end(), c.a_preset), listed.end()) << result.err;
    EXPECT_TRUE(std::is_sorted(listed.begin(), listed.end())) << result.err;
    for (const std::string& name : listed)
      EXPECT_TRUE(fs::is_regular_file(folder / (name + ".json"))) << name;
    EXPECT_FALSE(fs::exists(dir_ / "out.csv"));
  }
}

TEST_F(TransformCliTest, RankDeficientArrayIsRefused) {
  // Nine accelerometers, all at one point off the CG: angular acceleration is
  // unobservable, and no sensor reads the CG acceleration (nine at the CG
  // would be an acceleration-only array, docs/algorithms.md).
  std::string sensors;
  const char* slots[9] = {"cg_x", "cg_y", "cg_z", "yarm_z", "yarm_x", "xarm_z", "xarm_y", "zarm_x", "zarm_y"};
  const char* axes[9] = {"[1,0,0]", "[0,1,0]", "[0,0,1]", "[0,0,1]", "[1,0,0]",
                         "[0,0,1]", "[0,1,0]", "[1,0,0]", "[0,1,0]"};
  for (int i = 0; i < 9; ++i)
    sensors += std::string(i ? "," : "") + R"({"slot": ")" + slots[i] +
               R"(", "type": "linear", "position": [1,0,0], "axis": )" + axes[i] + R"(, "unit": "g"})";
  WriteText(dir_ / "flat.json", R"({"name": "flat", "length_unit": "in", "sensors": [)" + sensors + "]}");
  ExpectRefused(Transform(input_, (dir_ / "flat.json").string()), "rank");
}

TEST_F(TransformCliTest, MissingInputFileIsRefused) {
  ExpectRefused(Transform(dir_ / "nope.csv"), "nope.csv");
}

TEST_F(TransformCliTest, UsageErrorsExitTwo) {
  const CommandResult result =
      RunProgram(NAPKIN_BINARY, {"transform", "--array", "denton-3222", input_.string()});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_EQ(RunProgram(NAPKIN_BINARY, {"no-such-command"}).exit_code, 2);
}

}  // namespace
}  // namespace napkin::test_support
