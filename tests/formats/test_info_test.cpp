// What the readers take from real files besides samples: the dummy position
// of each channel, the test-level information, UDS-1992 INIVEL in m/s,
// CSV column maps and the note when channels are cropped to a common span.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "engine/units.h"
#include "formats/channel_map.h"
#include "formats/csv.h"
#include "formats/isomme.h"
#include "formats/uds1992.h"
#include "tests/formats/formats_test_util.h"
#include "tests/support/isomme_generator.h"
#include "tests/support/test_support.h"

namespace napkin::formats {
namespace {

using test_support::ExpectInputError;
using test_support::TempDir;
using test_support::WriteBytes;

TEST(IsoMmeTestInfoTest, PositionsAndTestInformationOfAGeneratedLabTest) {
  TempDir dir;
  const test_support::GeneratedIsoMme generated = test_support::WriteMultiDummyIsoMme(dir / "MD0001");
  const IsoMmeTest test = ReadIsoMme(dir / "MD0001");
  ASSERT_EQ(test.channels.size(), 120U);
  for (std::size_t c = 0; c < test.channels.size(); ++c) {
    EXPECT_EQ(test.channels[c].code, generated.codes[c]);
    EXPECT_EQ(test.channels[c].position, generated.codes[c].substr(0, 2));
  }
  EXPECT_EQ(test.channels[1].unit, "\xC2\xB0/s");  // ISO-8859-1 degree sign read as UTF-8
  const TestInfo passenger = IsoMmeTestInfo(test, test.channels[6]);
  EXPECT_EQ(test.channels[6].code, "13HEAD0000HFACXA");
  EXPECT_EQ(passenger.test_number, "MD0001");
  EXPECT_EQ(passenger.title, generated.title);
  EXPECT_EQ(passenger.vehicle,
            "Kompaktwagen \xC3\x84"
            "4");
  EXPECT_EQ(passenger.dummy, "HF");
  EXPECT_EQ(passenger.date, "2019-05-21");
  EXPECT_EQ(passenger.laboratory,
            "Pr\xC3\xBC"
            "fstand M\xC3\xBCnchen");
}

TEST(UdsTestInfoTest, HeaderFieldsAndInivelInMetresPerSecond) {
  TempDir dir;
  UdsChannel channel;
  channel.test_number = 7;
  channel.title = "OBLIQUE";
  channel.test_source = "VRTC";
  channel.make = "HONDA";
  channel.model = "ACCORD";
  channel.occupant_type = "H3";
  channel.dummy_size = "05";
  channel.senatt = "HEAD CG";
  channel.senloc = "03";
  channel.axis = "XL";
  channel.initial_velocity = 90.0;
  channel.values = {1.0, 2.0};
  for (const auto& [dimsys, mps] :
       {std::pair<const char*, double>{"MET", 25.0}, {"SI", 90.0}, {"ENG", 40.2336}}) {
    channel.dimsys = dimsys;
    WriteUds1992(channel, dir / "c.001");
    const UdsChannel read = ReadUds1992(dir / "c.001");
    const RawChannel raw = ToRawChannel(read, dir / "c.001");
    EXPECT_EQ(raw.position, "03");
    ASSERT_TRUE(raw.initial_velocity_mps.has_value());
    EXPECT_NEAR(*raw.initial_velocity_mps, mps, 1e-9 * mps) << dimsys;
    const TestInfo info = UdsTestInfo(read);
    EXPECT_EQ(info.test_number, "7");
    EXPECT_EQ(info.title, "OBLIQUE");
    EXPECT_EQ(info.vehicle, "HONDA ACCORD");
    EXPECT_EQ(info.dummy, "H3 05");
    EXPECT_EQ(info.laboratory, "VRTC");
    EXPECT_EQ(info.date, "");
  }
  channel.initial_velocity = 0.0;
  WriteUds1992(channel, dir / "c.001");
  EXPECT_FALSE(ToRawChannel(ReadUds1992(dir / "c.001"), dir / "c.001").initial_velocity_mps);
}

TEST(TableTwoOneTest, OnlyNineFilesForAnArrayOfTableTwoOneSlots) {
  engine::ArrayGeometry array;
  for (const char* slot : {"cg_x", "cg_y", "cg_z"}) array.sensors.push_back({slot});
  EXPECT_TRUE(InTableTwoOneOrder(9, array));
  EXPECT_FALSE(InTableTwoOneOrder(8, array));
  EXPECT_EQ(TableTwoOneAssignment(array, "t"), (std::vector<std::size_t>{0, 1, 2}));
  array.sensors.push_back({"ars_x", engine::SensorKind::kAngularRate});
  EXPECT_FALSE(InTableTwoOneOrder(9, array));
}

TEST(ChannelMapTest, ColumnEntriesAreSlotsOfTheMap) {
  const ChannelMap map = ParseChannelMap(
      nlohmann::json::parse(
          R"({"slots": {"cg_x": {"column": "Head X"}, "cg_y": {"code": "??HEAD0000??ACY?"}}})"),
      "m.json");
  EXPECT_EQ(map.CsvColumns(), (std::vector<std::pair<std::string, std::string>>{{"cg_x", "Head X"}}));
  ExpectInputError(
      [] { ParseChannelMap(nlohmann::json::parse(R"({"slots": {"cg_x": {"axis": "XL"}}})"), "m.json"); },
      {"m.json", "slot \"cg_x\" has neither a \"code\" pattern nor a \"senatt\" nor a \"column\""});
}

TEST(CsvColumnMapTest, MappedColumnsFeedTheirSlots) {
  TempDir dir;
  engine::ArrayGeometry array;
  array.name = "two";
  array.sensors.push_back({"cg_x"});
  array.sensors.push_back({"cg_y"});
  WriteBytes(dir / "a.csv", "t,Y,X,cg_x\n0,1,2,3\n0.5,4,5,6\n");
  const CsvSignals read =
      ReadSignalsCsv(dir / "a.csv", &array, {{"time_s", "t"}, {"cg_x", "X"}, {"cg_y", "Y"}});
  EXPECT_EQ(read.signals.slots, (std::vector<std::string>{"cg_x", "cg_y"}));
  EXPECT_EQ(read.signals.dt_s, 0.5);
  EXPECT_EQ(read.signals.samples(1, 0), 5.0);
  EXPECT_EQ(read.signals.samples(1, 1), 4.0);
  ASSERT_EQ(read.warnings.size(), 1U);  // the unmapped "cg_x" column is not read
  EXPECT_NE(read.warnings[0].find("column \"cg_x\""), std::string::npos);
  ExpectInputError(
      [&] {
        ReadSignalsCsv(dir / "a.csv", &array, {{"time_s", "t"}, {"cg_y", "Q"}});
      },
      {"a.csv", "no column \"Q\" (mapped to slot \"cg_y\")"});
  ExpectInputError(
      [&] {
        ReadSignalsCsv(dir / "a.csv", &array, {{"time_s", "t"}, {"cg_z", "X"}});
      },
      {"a.csv", "slot \"cg_z\"", "does not have"});
  EXPECT_EQ(ParseCsvColumnOptions({"cg_x = Head X", "time_s=t"}),
            (CsvColumnMap{{"cg_x", "Head X"}, {"time_s", "t"}}));
  EXPECT_THROW(ParseCsvColumnOptions({"cg_x"}), UsageError);
  EXPECT_THROW(ParseCsvColumnOptions({"cg_x=a", "cg_x=b"}), UsageError);
}

TEST(AssembleSignalsTest, CroppingToTheCommonSpanIsNoted) {
  engine::ArrayGeometry array;
  array.name = "two";
  array.sensors.push_back({"cg_x"});
  array.sensors.push_back({"cg_y"});
  std::vector<RawChannel> channels(2);
  channels[0].code = "11HEAD0000H3ACXA";
  channels[0].unit = "g";
  channels[0].dt_s = 0.1;
  channels[0].t0_s = -0.2;
  channels[0].values = {1, 2, 3, 4, 5, 6};  // -0.2 ... 0.3
  channels[1] = channels[0];
  channels[1].code = "11HEAD0000H3ACYA";
  channels[1].t0_s = 0.0;
  channels[1].values = {7, 8, 9};  // 0 ... 0.2
  std::vector<std::string> notes;
  const engine::TestSignals signals = AssembleSignals(channels, {0, 1}, array, "T", &notes);
  EXPECT_EQ(signals.size(), 3);
  EXPECT_EQ(signals.samples(0, 0), 3.0);
  ASSERT_EQ(notes.size(), 1U);
  EXPECT_EQ(notes[0],
            "test T: the channels' time spans differ; all were cropped to the common span 0 s to 0.2 s, "
            "dropping samples of 11HEAD0000H3ACXA (3 samples).");
  notes.clear();
  AssembleSignals(channels, {1, 1}, array, "T", &notes);
  EXPECT_TRUE(notes.empty());
}

}  // namespace
}  // namespace napkin::formats
