// `napkin export --format isomme` and `--format uds` as other tools read
// them: the ISO-MME export carries ISO/TS 13499 channel codes (position,
// dummy type, filter letter of the filter napkin applied), `Channel frequency
// class`, `Reference channel` and an exact decimal `Sampling interval`, and
// re-imports to the same criteria (import -> run -> export -> import -> run);
// the UDS-1992 export writes the report's Appendix B files, read back by
// napkin's own reader within float32.
#include <gtest/gtest.h>

#include <map>
#include <nlohmann/json.hpp>

#include "engine/units.h"
#include "formats/csv.h"
#include "formats/isomme.h"
#include "formats/uds1992.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"

namespace napkin::cli {

using namespace napkin::test_support;
namespace {

class CliExportFormats : public ::testing::Test {
 protected:
  void SetUp() override {
    // CG accelerometers and angular-rate sensors: the channels an ISO-MME export holds.
    synth::RandomMotionOptions options;
    options.seed = 91;
    options.duration_s = 0.08;
    synth_ = synth::SynthRandomMotion(formats::LoadArray("6aw-cg"), options);
    formats::WriteSignalsCsv(synth_.signals, dir_ / "t91.csv");
    ASSERT_EQ(RunNapkin(dir_.path(), {"init"}).exit_code, 0);
    const RunResult import = Import({"t91.csv"});
    ASSERT_EQ(import.exit_code, 0) << import.err;
    const RunResult run = RunNapkin(dir_.path(), {"run"});
    ASSERT_EQ(run.exit_code, 0) << run.err;
  }

  RunResult Import(std::vector<std::string> paths) {
    std::vector<std::string> args = {"import", "--array", "6aw-cg",
                                     TripleFlag("--orientation", synth_.initial.orientation_rad),
                                     TripleFlag("--initial-velocity", synth_.initial.velocity_fixed_mps)};
    args.insert(args.end(), paths.begin(), paths.end());
    return RunNapkin(dir_.path(), args);
  }

  // The `query criteria` row of each test under `config`, by test id.
  std::map<std::string, nlohmann::json> Criteria(const std::string& config) {
    const RunResult query =
        RunNapkin(dir_.path(), {"query", "criteria", "--config", config, "--format", "json"});
    EXPECT_EQ(query.exit_code, 0) << query.err;
    std::map<std::string, nlohmann::json> rows;
    for (const nlohmann::json& row : nlohmann::json::parse(query.out)) rows[row.at("test_id")] = row;
    return rows;
  }

  napkin::test_support::TempDir dir_;
  synth::SyntheticTest synth_;
};

TEST_F(CliExportFormats, IsoMmeHeadersCarryCodesFilterClassAndTimeBase) {
  const RunResult exported = RunNapkin(dir_.path(), {"export", "--test", "t91", "--format", "isomme", "--out",
                                                     "iso", "--position", "13", "--dummy-type", "H3"});
  ASSERT_EQ(exported.exit_code, 0) << exported.err;
  const formats::IsoMmeTest back = formats::ReadIsoMme(dir_ / "iso");
  std::map<std::string, const formats::RawChannel*> by_code;
  for (const formats::RawChannel& channel : back.channels) by_code[channel.code] = &channel;
  // Default config: CFC 1000 on the accelerometers (A), CFC 60 on the rate sensors (D).
  for (const char* code : {"13HEAD0000H3ACXA", "13HEAD00GLH3ACZA", "13HEAD00GLH3VEYA", "13HEAD0000H3AVXD",
                           "13HEAD00GLH3AAZD", "13HEAD00GLH3ANXD", "13HEAD00DCH3ANYD", "13HEAD00GLH3QUWD"})
    EXPECT_TRUE(by_code.count(code)) << code;
  EXPECT_EQ(back.channels.size(), 34u);
  const std::string header = ReadText(dir_ / "iso" / "Channel" / "t91.001");
  for (const char* line :
       {"Channel code                :13HEAD0000H3ACXA\n", "Channel frequency class     :1000\n",
        "Reference channel           :implicit\n", "Sampling interval           :0.0001\n"})
    EXPECT_NE(header.find(line), std::string::npos) << line << " in\n" << header.substr(0, 600);
  const std::string omega = ReadText(dir_ / "iso" / "Channel" / "t91.013");
  EXPECT_NE(omega.find("Channel frequency class     :60\n"), std::string::npos) << omega.substr(0, 600);

  const RunResult bad = RunNapkin(
      dir_.path(), {"export", "--test", "t91", "--format", "isomme", "--out", "x", "--dummy-type", "h3x"});
  EXPECT_EQ(bad.exit_code, 2);
  ExpectOneSentenceError(bad, {"dummy type", "h3x"});
}

TEST_F(CliExportFormats, IsoMmeRoundTripGivesIdenticalCriteria) {
  // The default config but for bit-exact derived channels (the default float32
  // storage rounds them; docs/formats.md "Derived-channel storage").
  WriteText(dir_ / "float64.json", R"({"name": "float64", "storage": {"derived_channels": "float64"}})");
  ASSERT_EQ(RunNapkin(dir_.path(), {"run", "--config", "float64.json"}).exit_code, 0);
  ASSERT_EQ(RunNapkin(dir_.path(), {"export", "--test", "t91", "--config", "float64.json", "--format",
                                    "isomme", "--out", "derived"})
                .exit_code,
            0);
  // The default channel map finds the body-axis CG channels (fine locations 0000) and no other.
  const RunResult import = Import({"derived"});
  ASSERT_EQ(import.exit_code, 0) << import.err;
  // The exported channels are conditioned already: the second run applies no bias removal or filter.
  WriteText(dir_ / "as-exported.json",
            R"({"name": "as-exported", "filter": {"linear_cfc": "none", "angular_rate_cfc": "none"},
                "bias": {"mode": "none"}})");
  const RunResult run = RunNapkin(dir_.path(), {"run", "--config", "as-exported.json"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::map<std::string, nlohmann::json> first = Criteria("float64");
  std::map<std::string, nlohmann::json> second = Criteria("as-exported");
  ASSERT_TRUE(first.count("t91") && second.count("derived"));
  const nlohmann::json& original = first.at("t91");
  const nlohmann::json& again = second.at("derived");
  int compared = 0;
  for (const auto& [field, value] : original.items()) {
    if (!value.is_number()) continue;
    ASSERT_TRUE(again.at(field).is_number()) << field;
    const double a = value.get<double>();
    const double b = again.at(field).get<double>();
    EXPECT_NEAR(b, a, 1e-12 * std::max(1.0, std::abs(a))) << field;
    ++compared;
  }
  EXPECT_GE(compared, 25);
  EXPECT_GT(original.at("hic15").get<double>(), 0.0);
}

TEST_F(CliExportFormats, UdsExportWritesTheReportsFilesReadBackWithinFloat32) {
  db::Catalogue catalogue = OpenForReading(dir_ / "napkin.db");
  const db::TestId test = *catalogue.FindTestByExternalId("t91");
  const engine::Kinematics k = *catalogue.ReadKinematics(test, *catalogue.ReadLatestResultConfig(test));
  const double g = engine::kStandardGravity;
  struct Expected {
    std::string name;
    std::string yunits;
    std::string axis;
    std::function<double(Eigen::Index)> value;
  };
  const std::vector<Expected> expected = {
      {"Ft91AM00.00X", "G'S", "XF", [&](Eigen::Index i) { return k.acc_fixed(i, 0) / g; }},
      {"Ft91AM00.00Z", "G'S", "ZF", [&](Eigen::Index i) { return k.acc_fixed(i, 2) / g; }},
      {"Bt91ROTV.00Y", "RADIANS/SEC", "YB", [&](Eigen::Index i) { return k.omega_body(i, 1); }},
      {"Ft91ROTA.00X", "RADIANS/SEC**2", "XF", [&](Eigen::Index i) { return k.alpha_fixed(i, 0); }},
      {"Ft91DCOS.022", "DEGREES", "YV",
       [&](Eigen::Index i) { return k.dcos_rad(i, 1) * engine::kDegPerRad; }},
      {"Ft91ROTD.00Z", "DEGREES", "ZF",
       [&](Eigen::Index i) { return k.roll_pitch_yaw_rad(i, 2) * engine::kDegPerRad; }},
      {"Ft91ROTV.00X", "RADIANS/SEC", "XF", [&](Eigen::Index i) { return k.omega_fixed(i, 0); }},
      {"Ft91VM00.00Y", "IN/SEC", "YF",
       [&](Eigen::Index i) { return k.vel_fixed(i, 1) / engine::kMetresPerInch; }},
  };
  for (const char* numform : {"ieee", "vax", "sun"}) {
    const std::string out = std::string("uds-") + numform;
    std::vector<std::string> args = {"export", "--test", "t91", "--format", "uds", "--out", out};
    if (std::string(numform) != "ieee") args.insert(args.end(), {"--numform", numform});
    const RunResult exported = RunNapkin(dir_.path(), args);
    ASSERT_EQ(exported.exit_code, 0) << exported.err;
    EXPECT_EQ(std::distance(fs::directory_iterator(dir_ / out), fs::directory_iterator()), 21);
    for (const Expected& e : expected) {
      const formats::UdsChannel channel = formats::ReadUds1992(dir_ / out / e.name);
      EXPECT_EQ(formats::UdsNumberFormName(channel.number_form), util::ToUpper(numform)) << e.name;
      EXPECT_EQ(channel.yunits, e.yunits) << e.name;
      EXPECT_EQ(channel.axis, e.axis) << e.name;
      EXPECT_EQ(channel.senatt, "HEAD CG") << e.name;
      EXPECT_EQ(channel.del_s, 1e-4) << e.name;
      EXPECT_NEAR(channel.nfp * channel.del_s, k.time_s[0], 1e-12) << e.name;
      ASSERT_EQ(static_cast<Eigen::Index>(channel.values.size()), k.size()) << e.name;
      for (Eigen::Index i = 0; i < k.size(); ++i) {
        const double truth = e.value(i);
        // float32: half a unit in the last place of a 24-bit significand.
        ASSERT_NEAR(channel.values[static_cast<std::size_t>(i)], truth, std::abs(truth) * 0x1p-24 + 1e-37)
            << e.name << " sample " << i << " " << numform;
      }
    }
  }
}

}  // namespace
}  // namespace napkin::cli
