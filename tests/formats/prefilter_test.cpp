// Where a file records that a channel is already filtered (docs/formats.md:
// ISO-MME "Channel frequency class" and the code's filter letter, UDS-1992
// FCUT), the readers carry it into the signals; the processing config's a3ms
// definition; the conditioning record in the summary JSON.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "engine/cfc_filter.h"
#include "formats/channel_map.h"
#include "formats/html_report.h"
#include "formats/isomme.h"
#include "formats/processing_config_json.h"
#include "formats/summary_json.h"
#include "formats/uds1992.h"
#include "tests/formats/formats_test_util.h"
#include "tests/support/reference_arrays.h"
#include "tests/support/test_support.h"

namespace napkin::formats {
namespace {

using test_support::TempDir;

std::string ChannelText(const std::string& code, const std::string& frequency_class) {
  std::string text = "Channel code                :" + code + "\r\n";
  if (!frequency_class.empty()) text += "Channel frequency class     :" + frequency_class + "\r\n";
  text += "Sampling interval           :0.001\r\nUnit                        :g\r\n";
  text += "Time of first sample        :0\r\nNumber of samples           :3\r\n1\r\n2\r\n3\r\n";
  return text;
}

// Reads one channel file written with `code` and `frequency_class` ("" = no such line).
std::optional<double> PrefilterOf(const std::string& code, const std::string& frequency_class) {
  TempDir dir;
  std::filesystem::create_directories(dir / "t" / "Channel");
  test_support::WriteBytes(dir / "t" / "t.mme", "Data format                 :ISO-MME\r\n");
  test_support::WriteBytes(dir / "t" / "Channel" / "t.chn", "Number of channels          :1\r\n");
  test_support::WriteBytes(dir / "t" / "Channel" / "t.001", ChannelText(code, frequency_class));
  const IsoMmeTest test = ReadIsoMme(dir / "t");
  return test.channels.at(0).prefiltered_cfc;
}

TEST(IsoMmePrefilter, FilterLetterAndFrequencyClassHeader) {
  EXPECT_EQ(PrefilterOf("11HEAD0000H3ACXA", ""), 1000.0);
  EXPECT_EQ(PrefilterOf("11HEAD0000H3ACXB", ""), 600.0);
  EXPECT_EQ(PrefilterOf("11HEAD0000H3ACXC", ""), 180.0);
  EXPECT_EQ(PrefilterOf("11HEAD0000H3ACXd", ""), 60.0);
  EXPECT_EQ(PrefilterOf("11HEAD0000H3ACX0", ""), std::nullopt);  // unfiltered
  EXPECT_EQ(PrefilterOf("11HEAD0000H3ACXX", ""), std::nullopt);  // class not stated
  // The header's class wins over the letter; NOVALUE leaves the letter.
  EXPECT_EQ(PrefilterOf("11HEAD0000H3ACXA", "180"), 180.0);
  EXPECT_EQ(PrefilterOf("11HEAD0000H3ACX0", "1000"), 1000.0);
  EXPECT_EQ(PrefilterOf("11HEAD0000H3ACXB", "NOVALUE"), 600.0);
  EXPECT_EQ(PrefilterOf("11HEAD0000H3ACX0", "NOVALUE"), std::nullopt);

  EXPECT_EQ(IsoMmeFilterLetter(1000.0), 'A');
  EXPECT_EQ(IsoMmeFilterLetter(60.0), 'D');
  EXPECT_EQ(IsoMmeFilterLetter(100.0), std::nullopt);
}

TEST(IsoMmePrefilter, WriterRecordsAndReaderRestoresThePrefilter) {
  TempDir dir;
  const engine::ArrayGeometry array = test_support::SixAOmegaCg();
  engine::TestSignals signals = test_support::MakeSignals(array, 50, 1e-4, -0.001);
  signals.prefiltered_cfc = {engine::kCfc1000, engine::kCfc1000, engine::kCfc1000,
                             std::nullopt,     std::nullopt,     75.0};
  const ChannelMap map = LoadChannelMap("default");
  WriteIsoMme(signals, array, map, dir / "t", "T1");
  const IsoMmeTest written = ReadIsoMme(dir / "t");
  EXPECT_EQ(written.channels.at(0).code.back(), 'A');
  EXPECT_EQ(written.channels.at(3).code.back(), '0');
  const engine::TestSignals read = ReadIsoMmeSignals(dir / "t", array, map);
  ASSERT_EQ(read.prefiltered_cfc.size(), 6u);
  for (Eigen::Index c = 0; c < 6; ++c) EXPECT_EQ(read.PrefilteredCfc(c), signals.PrefilteredCfc(c)) << c;
  EXPECT_EQ(read.samples, signals.samples);

  // Raw signals stay raw: no vector at all.
  const engine::TestSignals raw = test_support::MakeSignals(array, 50, 1e-4, 0.0);
  WriteIsoMme(raw, array, map, dir / "raw", "T2");
  EXPECT_TRUE(ReadIsoMmeSignals(dir / "raw", array, map).prefiltered_cfc.empty());
}

TEST(UdsPrefilter, FcutIsThePrefilterPrefIsInformative) {
  TempDir dir;
  for (const UdsNumberForm form : {UdsNumberForm::kIeee, UdsNumberForm::kVax, UdsNumberForm::kSun}) {
    UdsChannel channel;
    channel.number_form = form;
    channel.senatt = "HEAD CG";
    channel.axis = "XL";
    channel.values = {1.0, 2.0, 3.0};
    channel.prefilter_hz = 3000.0;
    channel.filter_cutoff_hz = 1000.0;
    const std::filesystem::path path = dir / ("f." + std::string(UdsNumberFormName(form)));
    WriteUds1992(channel, path);
    const UdsChannel read = ReadUds1992(path);
    EXPECT_EQ(read.prefilter_hz, 3000.0);
    EXPECT_EQ(read.filter_cutoff_hz, 1000.0);
    EXPECT_EQ(ToRawChannel(read, path).prefiltered_cfc, 600.0);  // FCUT 1000 Hz: CFC 600's cut-off

    channel.filter_cutoff_hz = 0.0;  // only the anti-aliasing prefilter: raw
    WriteUds1992(channel, path);
    EXPECT_EQ(ToRawChannel(ReadUds1992(path), path).prefiltered_cfc, std::nullopt);
  }
}

TEST(A3msConfigJson, DefinitionParsesAndDefaultKeepsTheCanonicalForm) {
  const engine::ProcessingConfig defaults;
  EXPECT_EQ(ProcessingConfigToJson(defaults).count("a3ms"), 0u);  // earlier configs keep their hash
  const engine::ProcessingConfig continuous =
      ParseProcessingConfig(nlohmann::json::parse(R"({"a3ms": {"definition": "continuous"}})"), "test");
  EXPECT_EQ(continuous.a3ms.definition, engine::A3msDefinition::kContinuous);
  EXPECT_EQ(ProcessingConfigToJson(continuous)["a3ms"].dump(), R"({"definition":"continuous"})");
  EXPECT_EQ(ParseProcessingConfig(ProcessingConfigToJson(continuous), "again").a3ms.definition,
            engine::A3msDefinition::kContinuous);
  const engine::ProcessingConfig cumulative =
      ParseProcessingConfig(nlohmann::json::parse(R"({"a3ms": {"definition": "cumulative"}})"), "test");
  EXPECT_EQ(CanonicalProcessingConfig(cumulative), CanonicalProcessingConfig(defaults));
  test_support::ExpectInputError(
      [] { ParseProcessingConfig(nlohmann::json::parse(R"({"a3ms": {"definition": "sliding"}})"), "cfg"); },
      {"cfg", "a3ms.definition", "\"cumulative\", \"continuous\""});
}

TEST(ConditioningJson, SummaryListsWhatWasDoneToEachChannel) {
  engine::TestSummary summary;
  EXPECT_FALSE(SummaryToJson(summary, "T", "", "").contains("conditioning"));
  engine::ChannelConditioning skipped;
  skipped.channel = "cg_x";
  skipped.prefiltered_cfc = 1000.0;
  skipped.filter_skipped_prefiltered = true;
  skipped.bias_removed = 0.25;
  skipped.bias_window_start_s = -0.05;
  skipped.bias_window_end_s = -0.0001;
  engine::ChannelConditioning filtered;
  filtered.channel = "ars_x";
  filtered.filter_cfc = 60.0;
  filtered.time_shift_s = 0.002;
  summary.conditioning = {skipped, filtered};
  const nlohmann::ordered_json json = SummaryToJson(summary, "T", "", "");
  ASSERT_EQ(json["conditioning"].size(), 2u);
  EXPECT_EQ(
      json["conditioning"][0].dump(),
      R"({"channel":"cg_x","filter":"none, prefiltered at CFC 1000","filter_cfc":null,)"
      R"("prefiltered_cfc":1000.0,"bias_removed":0.25,"bias_window_s":[-0.05,-0.0001],"time_shift_s":0.0})");
  EXPECT_EQ(json["conditioning"][1].dump(),
            R"({"channel":"ars_x","filter":"CFC 60","filter_cfc":60.0,"prefiltered_cfc":null,)"
            R"("bias_removed":0.0,"bias_window_s":null,"time_shift_s":0.002})");
}

TEST(ConditioningReport, EachTestShowsItsConditioningTable) {
  engine::Kinematics kinematics;
  kinematics.Resize(100);
  kinematics.time_s.setLinSpaced(100, 0.0, 0.0099);
  engine::TestSummary summary;
  engine::ChannelConditioning skipped;
  skipped.channel = "cg_x";
  skipped.prefiltered_cfc = 1000.0;
  skipped.filter_skipped_prefiltered = true;
  skipped.bias_removed = 0.5;
  skipped.bias_window_start_s = -0.002;
  skipped.bias_window_end_s = -0.0001;
  summary.conditioning = {skipped};
  std::vector<ReportTest> tests;
  tests.push_back(MakeReportTest("v1", "s", "a", "default", summary, kinematics));
  const std::string html = RenderHtmlReport(ReportHeader{}, {}, tests);
  EXPECT_NE(html.find("<h3>Conditioning</h3>"), std::string::npos);
  EXPECT_NE(html.find("<tr><td>cg_x</td><td>none, prefiltered at CFC 1000</td><td>0.5000</td>"
                      "<td>-2.000 to -0.1000</td><td>0</td></tr>"),
            std::string::npos);
}

}  // namespace
}  // namespace napkin::formats
