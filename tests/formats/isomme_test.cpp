#include "formats/isomme.h"

#include <gtest/gtest.h>

#include "engine/units.h"
#include "formats/channel_map.h"
#include "tests/formats/formats_test_util.h"
#include "tests/support/reference_arrays.h"
#include "tests/support/test_support.h"

namespace napkin::formats {
namespace {

using test::ExpectInputError;
using testing::TempDir;

TEST(ChannelMapTest, CodePatterns) {
  EXPECT_TRUE(CodeMatches("??HEAD0000??ACX?", "11HEAD0000H3ACXA"));
  EXPECT_TRUE(CodeMatches("??HEAD0000??ACX?", "13head0000h3acxp"));
  EXPECT_FALSE(CodeMatches("??HEAD0000??ACX?", "11HEAD0000H3ACYA"));
  EXPECT_FALSE(CodeMatches("??HEAD0000??ACX?", "11HEAD0000H3ACX"));
  EXPECT_FALSE(CodeMatches("??HEADCG????ACX?", "11HEAD0000H3ACXA"));
  EXPECT_TRUE(CodeMatches("??HEADCG????ACX?", "11HEADCG0000ACXP"));
}

TEST(ChannelMapTest, PresetsCoverTheirSlots) {
  const ChannelMap standard = LoadChannelMap("default");
  for (const char* slot : {"cg_x", "cg_y", "cg_z", "ars_x", "ars_y", "ars_z"}) EXPECT_NE(standard.Find(slot), nullptr) << slot;
  EXPECT_EQ(standard.Find("yarm_z"), nullptr);
  const ChannelMap nap = LoadChannelMap("nap-example");
  for (const char* slot : engine::kNapSlots) EXPECT_NE(nap.Find(slot), nullptr) << slot;
}

TEST(ChannelMapTest, BadMapsNameFileAndSlot) {
  TempDir dir;
  auto expect = [&](const std::string& name, const std::string& text, const std::string& fragment) {
    test::WriteBytes(dir / name, text);
    ExpectInputError([&] { ReadChannelMap(dir / name); }, {(dir / name).string(), fragment});
  };
  expect("short.json", R"({"slots": {"cg_x": {"code": "??HEADCG??ACX?"}}})", "slot \"cg_x\": code pattern \"??HEADCG??ACX?\" has 14 characters");
  expect("empty.json", R"({"slots": {"cg_x": {}}})", "slot \"cg_x\" has neither");
  expect("noslots.json", R"({"name": "x"})", "no \"slots\"");
  expect("type.json", R"({"slots": {"cg_x": {"code": 5}}})", "slot \"cg_x\": \"code\" must be a string");
}

TEST(SignalUnitTest, SpellingsOfBothFormats) {
  using engine::SensorKind;
  const std::pair<const char*, double> linear[] = {{"g", engine::kStandardGravity}, {"G'S", engine::kStandardGravity},
                                                   {"m/s**2", 1.0}, {"M/SEC**2", 1.0}, {"m/s^2", 1.0},
                                                   {"FT/SEC**2", 0.3048}, {"IN/SEC**2", 0.0254}};
  for (const auto& [unit, factor] : linear) {
    const auto parsed = ParseSignalUnit(unit, "x");
    ASSERT_TRUE(parsed) << unit;
    EXPECT_EQ(parsed->kind, SensorKind::kLinear) << unit;
    EXPECT_DOUBLE_EQ(parsed->si_per_unit, factor) << unit;
  }
  const std::pair<const char*, double> rates[] = {{"rad/s", 1.0}, {"RADIANS/SECOND", 1.0}, {"DEG/SEC", engine::kPi / 180},
                                                  {"deg/s", engine::kPi / 180}, {"\xC2\xB0/s", engine::kPi / 180}};
  for (const auto& [unit, factor] : rates) {
    const auto parsed = ParseSignalUnit(unit, "x");
    ASSERT_TRUE(parsed) << unit;
    EXPECT_EQ(parsed->kind, SensorKind::kAngularRate) << unit;
    EXPECT_DOUBLE_EQ(parsed->si_per_unit, factor) << unit;
  }
  EXPECT_FALSE(ParseSignalUnit("NOVALUE", "x"));
  EXPECT_FALSE(ParseSignalUnit("  ", "x"));
  ExpectInputError([] { ParseSignalUnit("kN", "file.003"); }, {"file.003", "unrecognised unit \"kN\""});
}

TEST(IsoMmeTest, RawSignalsRoundTripForEveryPreset) {
  TempDir dir;
  const ChannelMap nap = LoadChannelMap("nap-example");
  const ChannelMap standard = LoadChannelMap("default");
  struct Case {
    engine::ArrayGeometry array;
    const ChannelMap* map;
  };
  const Case cases[] = {{testing::Denton3222(), &nap}, {testing::VolpeTable42(), &nap}, {testing::SixAOmegaCg(), &standard}};
  for (const Case& c : cases) {
    const engine::TestSignals written = test::MakeSignals(c.array, 517, 1e-4, -0.005);
    const auto folder = dir / c.array.name;
    WriteIsoMme(written, c.array, *c.map, folder, "T" + c.array.name);
    const engine::TestSignals read = ReadIsoMmeSignals(folder, c.array, *c.map);
    EXPECT_EQ(read.slots, written.slots);
    EXPECT_TRUE((read.samples.array() == written.samples.array()).all()) << c.array.name;
    EXPECT_EQ(read.dt_s, written.dt_s);
    EXPECT_EQ(read.t0_s, written.t0_s);
    const IsoMmeTest test = ReadIsoMme(folder / ("T" + c.array.name + ".mme"));
    EXPECT_EQ(test.TestNumber(), "T" + c.array.name);
  }
  // Writing again replaces the folder as a whole.
  const engine::TestSignals shorter = test::MakeSignals(testing::SixAOmegaCg(), 10, 1e-3, 0.0);
  WriteIsoMme(shorter, testing::SixAOmegaCg(), standard, dir / "6aw-cg", "T6aw-cg");
  EXPECT_EQ(ReadIsoMmeSignals(dir / "6aw-cg", testing::SixAOmegaCg(), standard).size(), 10);
}

// Channel files as another program writes them: CRLF, ISO-8859-1 names, tab
// padding, NOVALUE fields.

std::string ChannelText(const std::string& code, const std::string& unit, double dt, double t0,
                        const std::vector<std::string>& values, long declared = -1) {
  std::string text = "Channel code                :" + code + "\r\n";
  text += "Name of the channel\t\t:T\xEAte " + code + "\r\n";  // ISO-8859-1 e-circumflex
  text += "Laboratory channel code     :NOVALUE\r\n";
  text += "Sampling interval           :" + std::to_string(dt) + "\r\n";
  text += "Unit                        :" + unit + "\r\n";
  text += "Time of first sample        :" + std::to_string(t0) + "\r\n";
  text += "Number of samples           :" + std::to_string(declared >= 0 ? declared : static_cast<long>(values.size())) + "\r\n";
  text += "Data status                 :ok\r\n";
  for (const std::string& value : values) text += value + "\r\n";
  return text;
}

std::vector<std::string> Ramp(int count, double start, double step) {
  std::vector<std::string> values;
  for (int i = 0; i < count; ++i) values.push_back(std::to_string(start + step * i));
  return values;
}

void WriteFolder(const std::filesystem::path& folder, const std::vector<std::string>& channels) {
  std::filesystem::create_directories(folder / "Channel");
  test::WriteBytes(folder / "test.mme", "Data format                 :ISO-MME\r\nTest number                 :SN-77\r\n");
  std::string chn = "Number of channels          :" + std::to_string(channels.size()) + "\r\n";
  test::WriteBytes(folder / "Channel" / "test.chn", chn);
  for (std::size_t i = 0; i < channels.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "test.%03zu", i + 1);
    test::WriteBytes(folder / "Channel" / name, channels[i]);
  }
}

TEST(IsoMmeTest, ReadsForeignFolderOnCommonTimeSpanInSlotUnits) {
  TempDir dir;
  const engine::ArrayGeometry array = testing::SixAOmegaCg();
  WriteFolder(dir / "t", {
                             ChannelText("11NECKUP0000H3FOXA", "kN", 0.001, 0.0, Ramp(5, 0, 1)),  // not a head channel
                             ChannelText("11HEAD0000H3ACXA", "g", 0.001, -0.002, Ramp(10, 0, 1)),
                             ChannelText("11HEAD0000H3ACYA", "m/s**2", 0.001, 0.0, Ramp(10, 0, 9.80665)),
                             ChannelText("11HEAD0000H3ACZA", "g", 0.001, -0.001, Ramp(10, 100, 1)),
                             ChannelText("11HEAD0000H3AVXA", "deg/s", 0.001, 0.0, Ramp(10, 0, 180)),
                             ChannelText("11HEAD0000H3AVYA", "rad/s", 0.001, 0.0, Ramp(10, 5, 0)),
                             ChannelText("11HEAD0000H3AVZA", "rad/s", 0.001, 0.0, Ramp(10, 6, 0)),
                         });
  const engine::TestSignals signals = ReadIsoMmeSignals(dir / "t", array, LoadChannelMap("default"));
  // Common span: 0 ... 0.007 s (cg_x runs -0.002 ... 0.007).
  ASSERT_EQ(signals.size(), 8);
  EXPECT_NEAR(signals.t0_s, 0.0, 1e-15);
  EXPECT_EQ(signals.dt_s, 0.001);
  for (int k = 0; k < 8; ++k) {
    EXPECT_NEAR(signals.samples(k, 0), k + 2, 1e-12);          // cg_x in g, shifted by 2 samples
    EXPECT_NEAR(signals.samples(k, 1), k, 1e-12);              // m/s**2 -> g
    EXPECT_NEAR(signals.samples(k, 2), 101 + k, 1e-12);        // shifted by 1 sample
    EXPECT_NEAR(signals.samples(k, 3), k * engine::kPi, 1e-9);  // deg/s -> rad/s
    EXPECT_EQ(signals.samples(k, 4), 5.0);
  }
  const IsoMmeTest test = ReadIsoMme(dir / "t");
  EXPECT_EQ(test.TestNumber(), "SN-77");
  EXPECT_EQ(test.channels[1].name, "T\xC3\xAAte 11HEAD0000H3ACXA");  // converted to UTF-8
}

TEST(IsoMmeTest, ErrorsNameFileChannelOrSlot) {
  TempDir dir;
  const engine::ArrayGeometry array = testing::SixAOmegaCg();
  const ChannelMap map = LoadChannelMap("default");
  std::vector<std::string> good;
  for (const char* code : {"11HEAD0000H3ACXA", "11HEAD0000H3ACYA", "11HEAD0000H3ACZA"})
    good.push_back(ChannelText(code, "g", 0.001, 0.0, Ramp(6, 0, 1)));
  for (const char* code : {"11HEAD0000H3AVXA", "11HEAD0000H3AVYA", "11HEAD0000H3AVZA"})
    good.push_back(ChannelText(code, "rad/s", 0.001, 0.0, Ramp(6, 0, 1)));
  int counter = 0;
  auto expect = [&](std::vector<std::string> channels, const std::vector<std::string>& fragments) {
    const auto folder = dir / ("case" + std::to_string(++counter));
    WriteFolder(folder, channels);
    ExpectInputError([&] { ReadIsoMmeSignals(folder, array, map); }, fragments);
    return folder;
  };
  {
    auto channels = good;
    auto values = Ramp(6, 0, 1);
    values[3] = "NOVALUE";
    channels[2] = ChannelText("11HEAD0000H3ACZA", "g", 0.001, 0.0, values);
    expect(channels, {"test.003", "sample 4", "line 12", "NOVALUE"});
  }
  {
    auto channels = good;
    channels[1] = ChannelText("11HEAD0000H3ACYA", "g", 0.001, 0.0, Ramp(6, 0, 1), 9);
    expect(channels, {"test.002", "declares 9 samples but the file holds 6"});
  }
  {
    auto channels = good;
    channels[4] = ChannelText("11HEAD0000H3AVYA", "rad/s", 0.0005, 0.0, Ramp(6, 0, 1));
    expect(channels, {"11HEAD0000H3ACXA", "11HEAD0000H3AVYA", "share the sampling interval"});
  }
  {
    auto channels = good;
    channels[5] = ChannelText("11HEAD0000H3AVZA", "rad/s", 0.001, 1.0, Ramp(6, 0, 1));
    expect(channels, {"SN-77", "do not overlap"});
  }
  {
    auto channels = good;
    channels.push_back(ChannelText("11HEADCG0000ACXP", "g", 0.001, 0.0, Ramp(6, 0, 1)));
    expect(channels, {"slot \"cg_x\" is matched by two channels", "11HEAD0000H3ACXA", "11HEADCG0000ACXP"});
  }
  {
    auto channels = good;
    channels.erase(channels.begin() + 4);
    expect(channels, {"no channel matches slot \"ars_y\""});
  }
  {
    auto channels = good;
    channels[3] = ChannelText("11HEAD0000H3AVXA", "g", 0.001, 0.0, Ramp(6, 0, 1));  // acceleration unit on a rate code
    expect(channels, {"no channel matches slot \"ars_x\""});
  }
  {
    auto channels = good;
    channels[0] = ChannelText("11HEAD0000H3ACXA", "g", 0.001, 0.0, {"0", "1", "x2", "3", "4", "5"});
    expect(channels, {"test.001", "sample 3", "\"x2\", not a finite number"});
  }
  {
    auto channels = good;
    std::string text = channels[0];
    text.erase(text.find("Sampling interval"), text.find("Unit") - text.find("Sampling interval"));
    channels[0] = text;
    expect(channels, {"test.001", "no \"Sampling interval\""});
  }
  {
    const auto folder = dir / "nochannel";
    std::filesystem::create_directories(folder);
    test::WriteBytes(folder / "a.mme", "Data format :ISO-MME\n");
    ExpectInputError([&] { ReadIsoMme(folder); }, {folder.string(), "no Channel folder"});
    std::filesystem::create_directories(folder / "Channel");
    test::WriteBytes(folder / "Channel" / "a.chn", "Number of channels :2\n");
    test::WriteBytes(folder / "Channel" / "a.001", ChannelText("11HEAD0000H3ACXA", "g", 0.001, 0.0, Ramp(6, 0, 1)));
    ExpectInputError([&] { ReadIsoMme(folder); }, {"a.002", "channel 2 of 2", "missing"});
  }
  {
    // A map that sends one channel to two slots.
    test::WriteBytes(dir / "twice.json", R"({"name": "twice", "slots": {
        "cg_x": {"code": "??HEAD0000??ACX?"}, "cg_y": {"code": "??HEAD0000??ACX?"}, "cg_z": {"code": "??HEAD0000??ACZ?"},
        "ars_x": {"code": "??HEAD0000??AVX?"}, "ars_y": {"code": "??HEAD0000??AVY?"}, "ars_z": {"code": "??HEAD0000??AVZ?"}}})");
    WriteFolder(dir / "twice", good);
    ExpectInputError([&] { ReadIsoMmeSignals(dir / "twice", array, ReadChannelMap(dir / "twice.json")); },
                     {"11HEAD0000H3ACXA", "matched by both slot \"cg_x\" and slot \"cg_y\""});
  }
  WriteFolder(dir / "good", good);
  EXPECT_EQ(ReadIsoMmeSignals(dir / "good", array, map).size(), 6);
  ExpectInputError([&] { ReadIsoMmeSignals(dir / "good", testing::Denton3222(), map); },
                   {"has no entry for slot \"yarm_z\""});
}

TEST(IsoMmeTest, DerivedExportReadsBack) {
  TempDir dir;
  engine::Kinematics k;
  k.Resize(20);
  for (Eigen::Index i = 0; i < 20; ++i) {
    k.time_s[i] = -0.001 + 0.0005 * static_cast<double>(i);
    for (engine::Series3* s : {&k.omega_body, &k.alpha_body, &k.omega_fixed, &k.alpha_fixed, &k.acc_body, &k.acc_fixed,
                               &k.vel_fixed, &k.pos_fixed, &k.roll_pitch_yaw_rad, &k.dcos_rad})
      s->row(i) << 1.0 * i, 2.0 * i, 3.0 * i;
    k.quat_fixed_from_body.row(i) << 1, 0, 0, 0;
  }
  WriteDerivedIsoMme(k, dir / "export", "E1");
  const IsoMmeTest test = ReadIsoMme(dir / "export");
  ASSERT_EQ(test.channels.size(), 34u);
  for (const RawChannel& channel : test.channels) {
    EXPECT_EQ(channel.code.size(), 16u) << channel.code;
    EXPECT_EQ(channel.values.size(), 20u);
    EXPECT_NEAR(channel.dt_s, 0.0005, 1e-15);
    EXPECT_NEAR(channel.t0_s, -0.001, 1e-15);
  }
  const auto find = [&](const std::string& code) -> const RawChannel& {
    for (const RawChannel& channel : test.channels)
      if (channel.code == code) return channel;
    throw std::runtime_error("no channel " + code);
  };
  EXPECT_NEAR(find("11HEADCG00FXACY0").values[7], 14.0 / engine::kStandardGravity, 1e-12);
  EXPECT_EQ(find("11HEADCG00FXACY0").unit, "g");
  EXPECT_NEAR(find("11HEADCG0000AVZ0").values[5], 15.0, 1e-12);
  EXPECT_NEAR(find("11HEADCG00FXANX0").values[2], 2.0 * engine::kDegPerRad, 1e-9);
}

}  // namespace
}  // namespace napkin::formats
