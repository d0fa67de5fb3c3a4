// `napkin export` end to end: the stored derived channels as CSV (equal to
// `napkin transform` on the same input), ISO-MME (reads back to the stored
// kinematics), LS-DYNA keyword cards (integrating the exported velocities
// gives the stored displacement) and LC_FILE; clear errors without results.
#include <gtest/gtest.h>

#include <map>

#include "engine/units.h"
#include "formats/csv.h"
#include "formats/isomme.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/lsdyna_keyword.h"
#include "tests/support/test_support.h"

namespace napkin::cli {

using namespace napkin::test_support;
namespace {

class CliExport : public ::testing::Test {
 protected:
  void SetUp() override {
    synth_ = SynthNapTest(71, 0.1);
    formats::WriteSignalsCsv(synth_.signals, dir_ / "e0001.csv");
    ASSERT_EQ(RunNapkin(dir_.path(), {"init"}).exit_code, 0);
    const RunResult import = RunNapkin(
        dir_.path(), {"import", "--array", "denton-3222", "--series", "sled",
                      TripleFlag("--orientation", synth_.initial.orientation_rad),
                      TripleFlag("--initial-velocity", synth_.initial.velocity_fixed_mps), "e0001.csv"});
    ASSERT_EQ(import.exit_code, 0) << import.err;
  }

  RunResult Export(std::vector<std::string> args) {
    args.insert(args.begin(), {"export", "--test", "e0001"});
    return RunNapkin(dir_.path(), args);
  }

  napkin::test_support::TempDir dir_;
  synth::SyntheticTest synth_;
};

TEST_F(CliExport, ExportedCsvEqualsTransformOfTheSameFile) {
  ProcessAndStore(dir_ / "napkin.db", "e0001");
  const RunResult exported = Export({"--format", "csv", "--out", "exported.csv"});
  ASSERT_EQ(exported.exit_code, 0) << exported.err;
  const RunResult transformed =
      RunNapkin(dir_.path(), {"transform", "--array", "denton-3222",
                              TripleFlag("--orientation", synth_.initial.orientation_rad),
                              TripleFlag("--initial-velocity", synth_.initial.velocity_fixed_mps),
                              "e0001.csv", "--out", "transformed.csv"});
  ASSERT_EQ(transformed.exit_code, 0) << transformed.err;
  const std::string csv = ReadText(dir_ / "exported.csv");
  EXPECT_GT(Lines(csv).size(), 1000u);
  EXPECT_EQ(csv, ReadText(dir_ / "transformed.csv"));  // byte for byte
}

TEST_F(CliExport, IsoMmeExportReadsBackAsTheStoredKinematics) {
  const engine::ProcessedTest processed = ProcessAndStore(dir_ / "napkin.db", "e0001");
  const engine::Kinematics& k = processed.kinematics;
  const RunResult exported = Export({"--format", "isomme", "--out", "derived"});
  ASSERT_EQ(exported.exit_code, 0) << exported.err;
  const formats::IsoMmeTest back = formats::ReadIsoMme(dir_ / "derived");
  EXPECT_EQ(back.TestNumber(), "e0001");
  std::map<std::string, const formats::RawChannel*> by_code;
  for (const formats::RawChannel& channel : back.channels) by_code[channel.code] = &channel;

  const double g = engine::kStandardGravity;
  const std::vector<std::pair<std::string, std::function<double(Eigen::Index)>>> expected = {
      {"11HEAD00GL00VEXA", [&](Eigen::Index i) { return k.vel_fixed(i, 0); }},
      {"11HEAD00GL00VEZA", [&](Eigen::Index i) { return k.vel_fixed(i, 2); }},
      {"11HEAD00GL00DSYA", [&](Eigen::Index i) { return k.pos_fixed(i, 1); }},
      {"11HEAD000000AVYA", [&](Eigen::Index i) { return k.omega_body(i, 1); }},
      {"11HEAD00GL00AAZA", [&](Eigen::Index i) { return k.alpha_fixed(i, 2); }},
      {"11HEAD000000ACXA", [&](Eigen::Index i) { return k.acc_body(i, 0) / g; }},
      {"11HEAD00GL00QUWA", [&](Eigen::Index i) { return k.quat_fixed_from_body(i, 0); }},
      {"11HEAD00GL00ANZA", [&](Eigen::Index i) { return k.roll_pitch_yaw_rad(i, 2) * engine::kDegPerRad; }},
  };
  for (const auto& [code, value] : expected) {
    ASSERT_TRUE(by_code.count(code)) << code;
    const formats::RawChannel& channel = *by_code.at(code);
    ASSERT_EQ(static_cast<Eigen::Index>(channel.values.size()), k.size()) << code;
    EXPECT_NEAR(channel.dt_s, synth_.signals.dt_s, 1e-15) << code;
    EXPECT_NEAR(channel.t0_s, k.time_s[0], 1e-15) << code;
    for (Eigen::Index i = 0; i < k.size(); ++i) {
      // Twelve significant digits in the file.
      ASSERT_NEAR(channel.values[static_cast<std::size_t>(i)], value(i),
                  1e-11 * std::max(1.0, std::abs(value(i))))
          << code << " sample " << i;
    }
  }
}

TEST_F(CliExport, IsoMmeExportReimportsAsA6aOmegaTestWithTheStoredChannels) {
  const engine::ProcessedTest processed = ProcessAndStore(dir_ / "napkin.db", "e0001");
  const engine::Kinematics& k = processed.kinematics;
  ASSERT_EQ(Export({"--format", "isomme", "--out", "derived"}).exit_code, 0);
  // The exported body-axis CG acceleration and angular velocity are the
  // channels of a 6a-omega array at the CG.
  WriteText(dir_ / "body.json", R"({"name": "body", "slots": {
      "cg_x": {"code": "11HEAD000000ACX?"}, "cg_y": {"code": "11HEAD000000ACY?"}, "cg_z": {"code": "11HEAD000000ACZ?"},
      "ars_x": {"code": "11HEAD000000AVX?"}, "ars_y": {"code": "11HEAD000000AVY?"},
      "ars_z": {"code": "11HEAD000000AVZ?"}}})");
  const RunResult import =
      RunNapkin(dir_.path(), {"import", "--array", "6aw-cg", "--channel-map", "body.json", "derived"});
  ASSERT_EQ(import.exit_code, 0) << import.err;
  db::Catalogue catalogue = OpenForReading(dir_ / "napkin.db");
  const engine::TestSignals back = catalogue.ReadTestSignals(*catalogue.FindTestByExternalId("derived"));
  ASSERT_EQ(back.size(), k.size());
  EXPECT_NEAR(back.dt_s, synth_.signals.dt_s, 1e-15);
  EXPECT_EQ(back.slots, (std::vector<std::string>{"cg_x", "cg_y", "cg_z", "ars_x", "ars_y", "ars_z"}));
  for (int axis = 0; axis < 3; ++axis) {
    for (Eigen::Index i = 0; i < k.size(); ++i) {
      const double acc_g = k.acc_body(i, axis) / engine::kStandardGravity;
      ASSERT_NEAR(back.samples(i, axis), acc_g, 1e-11 * std::max(1.0, std::abs(acc_g))) << i;
      const double omega = k.omega_body(i, axis);
      ASSERT_NEAR(back.samples(i, 3 + axis), omega, 1e-11 * std::max(1.0, std::abs(omega))) << i;
    }
  }
}

using napkin::test_support::ParsedKeyword;
using napkin::test_support::ParseKeyword;
using napkin::test_support::Trapezoid;

TEST_F(CliExport, LsDynaVelocitiesIntegrateToTheStoredDisplacement) {
  const engine::ProcessedTest processed = ProcessAndStore(dir_ / "napkin.db", "e0001");
  const engine::Kinematics& k = processed.kinematics;
  const Eigen::Vector3d final_pos_m = k.pos_fixed.row(k.size() - 1).transpose();
  ASSERT_GT(final_pos_m.norm(), 1e-3);  // the motion moves the head (random initial velocity)
  for (const char* units : {"si", "english"}) {
    const RunResult exported =
        Export({"--format", "lsdyna", "--units", units, "--part", "7", "--out", "head.k"});
    ASSERT_EQ(exported.exit_code, 0) << exported.err;
    const ParsedKeyword parsed = ParseKeyword(dir_ / "head.k");
    ASSERT_EQ(parsed.curves.size(), 6u);
    const double per_metre = std::string(units) == "si" ? 1.0 : 1.0 / engine::kMetresPerInch;
    const auto first_curve = parsed.curves.begin();
    for (int c = 0; c < 3; ++c) {
      const auto& velocity = std::next(first_curve, c)->second;
      ASSERT_EQ(static_cast<Eigen::Index>(velocity.size()), k.size());
      EXPECT_NEAR(velocity.front().second, k.vel_fixed(0, c) * per_metre, 1e-6 * per_metre);
      // Within 0.1 % of the displacement.
      EXPECT_NEAR(Trapezoid(velocity), final_pos_m[c] * per_metre, 1e-3 * final_pos_m.norm() * per_metre)
          << units << " axis " << c;
    }
    ASSERT_EQ(parsed.motions.size(), 6u);
    const int dofs[6] = {1, 2, 3, 5, 6, 7};
    for (std::size_t i = 0; i < 6; ++i) {
      EXPECT_EQ(parsed.motions[i][0], 7);  // --part
      EXPECT_EQ(parsed.motions[i][1], dofs[i]);
      EXPECT_EQ(parsed.motions[i][2], 0);  // VAD: velocity
      EXPECT_TRUE(parsed.curves.count(static_cast<int>(parsed.motions[i][3])));
    }
  }
}

TEST_F(CliExport, LcFileHasSixCurvesOfEverySample) {
  const engine::ProcessedTest processed = ProcessAndStore(dir_ / "napkin.db", "e0001");
  const RunResult exported = Export({"--format", "lcfile", "--out", "LC_FILE.DAT"});
  ASSERT_EQ(exported.exit_code, 0) << exported.err;
  int curves = 0;
  for (const std::string& line : Lines(ReadText(dir_ / "LC_FILE.DAT"))) {
    if (line.rfind(" lcd", 0) != 0) continue;
    ++curves;
    EXPECT_EQ(std::stoll(line.substr(line.find_last_of(' ') + 1)), processed.kinematics.size()) << line;
  }
  EXPECT_EQ(curves, 6);
}

TEST_F(CliExport, WithoutResultsOrForAnUnknownTestItSaysWhatToDo) {
  const RunResult none = Export({"--format", "csv", "--out", "x.csv"});
  EXPECT_EQ(none.exit_code, 1);
  ExpectOneSentenceError(none, {"test 'e0001' has no results yet; run `napkin run` first."});
  EXPECT_FALSE(fs::exists(dir_ / "x.csv"));

  const RunResult unknown =
      RunNapkin(dir_.path(), {"export", "--test", "nope", "--format", "csv", "--out", "x.csv"});
  EXPECT_EQ(unknown.exit_code, 1);
  ExpectOneSentenceError(unknown, {"'nope'", "napkin.db"});

  ProcessAndStore(dir_ / "napkin.db", "e0001");
  // A config the test was never processed with.
  const std::string config_json = R"({"solver": "seed"})";
  WriteText(dir_ / "seed.json", config_json);
  const RunResult other = Export({"--format", "csv", "--config", "seed.json", "--out", "x.csv"});
  EXPECT_EQ(other.exit_code, 1);
  ExpectOneSentenceError(other, {"'e0001'", "no results for config 'seed.json'"});
  // The stored default config is found by its content.
  EXPECT_EQ(Export({"--format", "csv", "--config", "default", "--out", "x.csv"}).exit_code, 0);
  EXPECT_TRUE(fs::exists(dir_ / "x.csv"));

  const RunResult bad_format = Export({"--format", "xlsx", "--out", "x.xlsx"});
  EXPECT_EQ(bad_format.exit_code, 2);
}

}  // namespace
}  // namespace napkin::cli
