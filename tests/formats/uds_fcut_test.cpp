// UDS-1992 FCUT is the cut-off frequency (Hz) of the last filter applied
// (NHTSA-Tools doc/UDS_Vars.txt; docs/formats.md "UDS-1992 input"), not a
// class number: SAE J211's CFC 60 / 180 / 600 / 1000 are cut off at 100 /
// 300 / 1000 / 1650 Hz. A channel written with its class's cut-off is not
// filtered again at that class; an FCUT that is no J211 cut-off is a filter
// of unknown class, with a warning, and is filtered as configured.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/cfc_filter.h"
#include "engine/channel_conditioning.h"
#include "engine/processing.h"
#include "formats/array_json.h"
#include "formats/channel_map.h"
#include "formats/uds1992.h"
#include "synth/synthetic_tests.h"
#include "tests/support/test_support.h"
#include "util/text.h"

namespace napkin::formats {
namespace {

using test_support::TempDir;

struct CutoffOfClass {
  double fcut_hz;
  double cfc;
};
// J211's cut-offs, and the 1662 Hz NHTSA's files carry for CFC 1000.
constexpr CutoffOfClass kCutoffs[] = {
    {100.0, 60.0}, {300.0, 180.0}, {1000.0, 600.0}, {1650.0, 1000.0}, {1662.0, 1000.0}};

TEST(UdsFcut, IsReadAsTheCutoffOfAJ211Class) {
  TempDir dir;
  for (const CutoffOfClass& expected : kCutoffs) {
    UdsChannel channel;
    channel.senatt = "HEAD CG";
    channel.axis = "XL";
    channel.values = {1.0, 2.0, 3.0};
    channel.filter_cutoff_hz = expected.fcut_hz;
    const std::filesystem::path path = dir / "f.001";
    WriteUds1992(channel, path);
    const UdsChannel read = ReadUds1992(path);
    EXPECT_EQ(read.filter_cutoff_hz, expected.fcut_hz);
    EXPECT_TRUE(read.warnings.empty()) << read.warnings.front();
    EXPECT_EQ(ToRawChannel(read, path).prefiltered_cfc, expected.cfc) << "FCUT " << expected.fcut_hz;
  }
  EXPECT_EQ(engine::J211CutoffOfClass(engine::kCfc60), 100.0);
  EXPECT_EQ(engine::J211CutoffOfClass(engine::kCfc180), 300.0);
  EXPECT_EQ(engine::J211CutoffOfClass(engine::kCfc600), 1000.0);
  EXPECT_EQ(engine::J211CutoffOfClass(engine::kCfc1000), 1650.0);
  EXPECT_EQ(engine::J211CutoffOfClass(300.0), 500.0);  // another class: 5/3 CFC
  // Outside the 2 % band: no class.
  EXPECT_EQ(engine::J211ClassOfCutoff(1690.0), std::nullopt);
  EXPECT_EQ(engine::J211ClassOfCutoff(1615.0), std::nullopt);
  EXPECT_EQ(engine::J211ClassOfCutoff(180.0), std::nullopt);
}

TEST(UdsFcut, AnotherFrequencyIsAFilterOfUnknownClassWithAWarning) {
  TempDir dir;
  UdsChannel channel;
  channel.senatt = "HEAD CG";
  channel.axis = "XL";
  channel.values = {1.0, 2.0, 3.0};
  channel.filter_cutoff_hz = 500.0;
  const std::filesystem::path path = dir / "odd.001";
  WriteUds1992(channel, path);
  const UdsChannel read = ReadUds1992(path);
  ASSERT_EQ(read.warnings.size(), 1u);
  EXPECT_NE(read.warnings[0].find(path.string() + ": FCUT 500 Hz is no SAE J211 class cut-off"),
            std::string::npos)
      << read.warnings[0];
  EXPECT_EQ(ToRawChannel(read, path).prefiltered_cfc, engine::kPrefilteredClassUnknown);

  // Conditioning filters it as configured and says so.
  const engine::ArrayGeometry array = LoadArray("3a-cg");
  synth::RandomMotionOptions motion;
  motion.duration_s = 0.03;
  engine::TestSignals signals = synth::SynthRandomMotion(array, motion).signals;
  signals.prefiltered_cfc = {engine::kPrefilteredClassUnknown, std::nullopt, std::nullopt};
  const engine::TestSignals unfiltered = signals;
  engine::ProcessingConfig config;
  config.bias.mode = engine::BiasMode::kNone;
  const std::vector<engine::ChannelConditioning> records = engine::ApplyConditioning(array, signals, config);
  EXPECT_EQ(records[0].filter_cfc, engine::kCfc1000);
  EXPECT_FALSE(records[0].filter_skipped_prefiltered);
  EXPECT_NE(signals.samples.col(0), unfiltered.samples.col(0));
  EXPECT_EQ(engine::FilterDescription(records[0]), "CFC 1000 (prefiltered, class unknown)");
  EXPECT_EQ(engine::FilteredClass(records[0]), engine::kCfc1000);
  const std::vector<engine::Finding> findings = engine::ConditioningFindings(records);
  ASSERT_EQ(findings.size(), 1u);
  EXPECT_EQ(
      findings[0].detail,
      "channel cg_x is recorded in the file as filtered, at a class it does not name; napkin filtered it "
      "at CFC 1000 as configured.");
  engine::ChannelConditioning unfiltered_record = records[0];
  unfiltered_record.filter_cfc.reset();
  EXPECT_EQ(engine::FilterDescription(unfiltered_record), "none (prefiltered, class unknown)");
  EXPECT_EQ(engine::FilteredClass(unfiltered_record), std::nullopt);
}

// Three CG channels filtered at `cfc`, written as UDS-1992 files with FCUT
// `fcut_hz`, read and conditioned with the filter `cfc`: the samples reach
// the solver as written (no second filter) and the record says "prefiltered".
TEST(UdsFcut, ChannelsFilteredAtTheirClassAreNotFilteredAgain) {
  const engine::ArrayGeometry array = LoadArray("3a-cg");
  const ChannelMap map = LoadChannelMap("default");
  for (const CutoffOfClass& cutoff : kCutoffs) {
    SCOPED_TRACE("FCUT " + std::to_string(cutoff.fcut_hz));
    TempDir dir;
    synth::RandomMotionOptions motion;
    motion.seed = 7;
    motion.duration_s = 0.05;
    engine::TestSignals synth = synth::SynthRandomMotion(array, motion).signals;
    std::vector<std::filesystem::path> files;
    const char* axes[3] = {"XL", "YL", "ZL"};
    for (Eigen::Index c = 0; c < 3; ++c) {
      Eigen::VectorXd column = synth.samples.col(c);
      engine::CfcFilterInPlace(column, synth.dt_s, cutoff.cfc);
      UdsChannel channel;
      channel.senatt = "HEAD CG";
      channel.axis = axes[c];
      channel.nfp = static_cast<int>(std::lround(synth.t0_s / synth.dt_s));
      channel.del_s = synth.dt_s;
      channel.filter_cutoff_hz = cutoff.fcut_hz;
      channel.values.assign(column.data(), column.data() + column.size());
      files.push_back(dir / ("t0001.00" + std::to_string(c + 1)));
      WriteUds1992(channel, files.back());
    }
    engine::TestSignals signals = ReadUdsTest(files, array, &map, "t0001");
    ASSERT_EQ(signals.prefiltered_cfc.size(), 3u);
    const Eigen::MatrixXd as_read = signals.samples;
    engine::ProcessingConfig config;
    config.bias.mode = engine::BiasMode::kNone;
    config.filter.linear_cfc = cutoff.cfc;
    const std::vector<engine::ChannelConditioning> records =
        engine::ApplyConditioning(array, signals, config);
    EXPECT_EQ(signals.samples, as_read);  // bit for bit: not filtered again
    for (const engine::ChannelConditioning& record : records) {
      EXPECT_EQ(record.prefiltered_cfc, cutoff.cfc) << record.channel;
      EXPECT_TRUE(record.filter_skipped_prefiltered) << record.channel;
      EXPECT_EQ(engine::FilterDescription(record),
                "none, prefiltered at CFC " + util::FormatNumber(cutoff.cfc))
          << record.channel;
    }
  }
}

}  // namespace
}  // namespace napkin::formats
