#include "formats/isomme.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <numbers>
#include <ostream>
#include <string>
#include <vector>

#include "engine/units.h"
#include "formats/channel_map.h"
#include "tests/formats/formats_test_util.h"
#include "tests/support/named_cases.h"
#include "tests/support/reference_arrays.h"
#include "tests/support/test_support.h"

namespace napkin::formats {
namespace {

using test_support::ExpectInputError;
using test_support::TempDir;

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
  for (const char* slot : {"cg_x", "cg_y", "cg_z", "ars_x", "ars_y", "ars_z"})
    EXPECT_NE(standard.Find(slot), nullptr) << slot;
  EXPECT_EQ(standard.Find("yarm_z"), nullptr);
  const ChannelMap nap = LoadChannelMap("nap-example");
  for (const char* slot : engine::kNapSlots) EXPECT_NE(nap.Find(slot), nullptr) << slot;
}

// A channel map that cannot be used: the message names the file and the slot.
struct BadMapCase {
  const char* name;  // also the file's stem
  const char* text;
  const char* fragment;
};
void PrintTo(const BadMapCase& bad, std::ostream* os) { *os << bad.name << ".json"; }

class ChannelMapErrorTest : public ::testing::TestWithParam<BadMapCase> {};

TEST_P(ChannelMapErrorTest, NamesFileAndSlot) {
  TempDir dir;
  const std::filesystem::path path = dir / (std::string(GetParam().name) + ".json");
  test_support::WriteBytes(path, GetParam().text);
  ExpectInputError([&] { ReadChannelMap(path); }, {path.string(), GetParam().fragment});
}

INSTANTIATE_TEST_SUITE_P(
    BadMaps, ChannelMapErrorTest,
    ::testing::Values(BadMapCase{"short", R"({"slots": {"cg_x": {"code": "??HEADCG??ACX?"}}})",
                                 "slot \"cg_x\": code pattern \"??HEADCG??ACX?\" has 14 characters"},
                      BadMapCase{"empty", R"({"slots": {"cg_x": {}}})", "slot \"cg_x\" has neither"},
                      BadMapCase{"noslots", R"({"name": "x"})", "no \"slots\""},
                      BadMapCase{"type", R"({"slots": {"cg_x": {"code": 5}}})",
                                 "slot \"cg_x\": \"code\" must be a string"}),
    test_support::CaseName());

// A unit as ISO-MME or UDS-1992 files spell it, with the kind and SI factor
// it stands for.
struct UnitCase {
  const char* name;
  const char* unit;
  engine::SensorKind kind;
  double si_per_unit;
};
void PrintTo(const UnitCase& spelling, std::ostream* os) { *os << '"' << spelling.unit << '"'; }

class SignalUnitSpellingTest : public ::testing::TestWithParam<UnitCase> {};

TEST_P(SignalUnitSpellingTest, GivesKindAndFactor) {
  const UnitCase& spelling = GetParam();
  const auto parsed = ParseSignalUnit(spelling.unit, "x");
  ASSERT_TRUE(parsed) << spelling.unit;
  EXPECT_EQ(parsed->kind, spelling.kind) << spelling.unit;
  EXPECT_DOUBLE_EQ(parsed->si_per_unit, spelling.si_per_unit) << spelling.unit;
}

INSTANTIATE_TEST_SUITE_P(
    Linear, SignalUnitSpellingTest,
    ::testing::Values(UnitCase{"g", "g", engine::SensorKind::kLinear, engine::kStandardGravity},
                      UnitCase{"G_S", "G'S", engine::SensorKind::kLinear, engine::kStandardGravity},
                      UnitCase{"m_s2_fortran", "m/s**2", engine::SensorKind::kLinear, 1.0},
                      UnitCase{"M_SEC2_fortran", "M/SEC**2", engine::SensorKind::kLinear, 1.0},
                      UnitCase{"m_s2_caret", "m/s^2", engine::SensorKind::kLinear, 1.0},
                      UnitCase{"FT_SEC2", "FT/SEC**2", engine::SensorKind::kLinear, 0.3048},
                      UnitCase{"IN_SEC2", "IN/SEC**2", engine::SensorKind::kLinear, 0.0254}),
    test_support::CaseName());

INSTANTIATE_TEST_SUITE_P(
    AngularRate, SignalUnitSpellingTest,
    ::testing::Values(
        UnitCase{"rad_s", "rad/s", engine::SensorKind::kAngularRate, 1.0},
        UnitCase{"RADIANS_SECOND", "RADIANS/SECOND", engine::SensorKind::kAngularRate, 1.0},
        UnitCase{"DEG_SEC", "DEG/SEC", engine::SensorKind::kAngularRate, std::numbers::pi / 180},
        UnitCase{"deg_s", "deg/s", engine::SensorKind::kAngularRate, std::numbers::pi / 180},
        UnitCase{"degree_sign_s", "\xC2\xB0/s", engine::SensorKind::kAngularRate, std::numbers::pi / 180}),
    test_support::CaseName());

TEST(SignalUnitTest, NoUnitOrAnUnknownOne) {
  EXPECT_FALSE(ParseSignalUnit("NOVALUE", "x"));
  EXPECT_FALSE(ParseSignalUnit("  ", "x"));
  ExpectInputError([] { ParseSignalUnit("kN", "file.003"); }, {"file.003", "unrecognised unit \"kN\""});
}

// A reference array with the channel-map preset that names its slots.
struct PresetCase {
  const char* name;
  engine::ArrayGeometry (*array)();
  const char* map;
};
void PrintTo(const PresetCase& preset, std::ostream* os) { *os << preset.name << " with map " << preset.map; }

class IsoMmePresetTest : public ::testing::TestWithParam<PresetCase> {};

TEST_P(IsoMmePresetTest, RawSignalsRoundTrip) {
  TempDir dir;
  const engine::ArrayGeometry array = GetParam().array();
  const ChannelMap map = LoadChannelMap(GetParam().map);
  const engine::TestSignals written = test_support::MakeSignals(array, 517, 1e-4, -0.005);
  const auto folder = dir / array.name;
  WriteIsoMme(written, array, map, folder, "T" + array.name);
  const engine::TestSignals read = ReadIsoMmeSignals(folder, array, map);
  EXPECT_EQ(read.slots, written.slots);
  EXPECT_TRUE((read.samples.array() == written.samples.array()).all()) << array.name;
  EXPECT_EQ(read.dt_s, written.dt_s);
  EXPECT_EQ(read.t0_s, written.t0_s);
  const IsoMmeTest test = ReadIsoMme(folder / ("T" + array.name + ".mme"));
  EXPECT_EQ(test.TestNumber(), "T" + array.name);
}

INSTANTIATE_TEST_SUITE_P(
    EveryPreset, IsoMmePresetTest,
    ::testing::Values(PresetCase{"denton_3222", &test_support::Denton3222, "nap-example"},
                      PresetCase{"volpe_table4_2", &test_support::VolpeTable42, "nap-example"},
                      PresetCase{"six_a_omega_cg", &test_support::SixAOmegaCg, "default"}),
    test_support::CaseName());

// Issue 19 item 1: a folder is written beside what it holds, never replaced
// as a whole; a taken file name is refused before anything moves.
TEST(IsoMmeTest, WritingAgainIsRefusedAndRemovesNothing) {
  TempDir dir;
  const ChannelMap standard = LoadChannelMap("default");
  const engine::ArrayGeometry array = test_support::SixAOmegaCg();
  std::filesystem::create_directories(dir / "6aw-cg");
  test_support::WriteBytes(dir / "6aw-cg" / "notes.txt", "the user's\n");
  WriteIsoMme(test_support::MakeSignals(array, 517, 1e-4, -0.005), array, standard, dir / "6aw-cg",
              "T6aw-cg");
  const engine::TestSignals shorter = test_support::MakeSignals(array, 10, 1e-3, 0.0);
  EXPECT_THROW(WriteIsoMme(shorter, array, standard, dir / "6aw-cg", "T6aw-cg"), InputError);
  EXPECT_EQ(ReadIsoMmeSignals(dir / "6aw-cg", array, standard).size(), 517);
  EXPECT_EQ(test_support::ReadBytes(dir / "6aw-cg" / "notes.txt"), "the user's\n");
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir / "6aw-cg"))
    EXPECT_NE(entry.path().filename().string().front(), '.') << entry.path();  // no staging folder left
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
  text += "Number of samples           :" +
          std::to_string(declared >= 0 ? declared : static_cast<long>(values.size())) + "\r\n";
  text += "Data status                 :ok\r\n";
  for (const std::string& value : values) text += value + "\r\n";
  return text;
}

std::vector<std::string> Ramp(int count, double start, double step) {
  std::vector<std::string> values;
  values.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) values.push_back(std::to_string(start + step * i));
  return values;
}

void WriteFolder(const std::filesystem::path& folder, const std::vector<std::string>& channels) {
  std::filesystem::create_directories(folder / "Channel");
  test_support::WriteBytes(folder / "test.mme",
                           "Data format                 :ISO-MME\r\nTest number                 :SN-77\r\n");
  std::string chn = "Number of channels          :" + std::to_string(channels.size()) + "\r\n";
  test_support::WriteBytes(folder / "Channel" / "test.chn", chn);
  for (std::size_t i = 0; i < channels.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "test.%03zu", i + 1);
    test_support::WriteBytes(folder / "Channel" / name, channels[i]);
  }
}

TEST(IsoMmeTest, ReadsForeignFolderOnCommonTimeSpanInSlotUnits) {
  TempDir dir;
  const engine::ArrayGeometry array = test_support::SixAOmegaCg();
  WriteFolder(dir / "t",
              {
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
    EXPECT_NEAR(signals.samples(k, 0), k + 2, 1e-12);                // cg_x in g, shifted by 2 samples
    EXPECT_NEAR(signals.samples(k, 1), k, 1e-12);                    // m/s**2 -> g
    EXPECT_NEAR(signals.samples(k, 2), 101 + k, 1e-12);              // shifted by 1 sample
    EXPECT_NEAR(signals.samples(k, 3), k * std::numbers::pi, 1e-9);  // deg/s -> rad/s
    EXPECT_EQ(signals.samples(k, 4), 5.0);
  }
  const IsoMmeTest test = ReadIsoMme(dir / "t");
  EXPECT_EQ(test.TestNumber(), "SN-77");
  EXPECT_EQ(test.channels[1].name, "T\xC3\xAAte 11HEAD0000H3ACXA");  // converted to UTF-8
}

// Six good channels for the 6a-omega CG array (default map): three
// accelerometers in g, three rate sensors in rad/s, 6 samples at 1 kHz.
std::vector<std::string> GoodChannels() {
  std::vector<std::string> good;
  for (const char* code : {"11HEAD0000H3ACXA", "11HEAD0000H3ACYA", "11HEAD0000H3ACZA"})
    good.push_back(ChannelText(code, "g", 0.001, 0.0, Ramp(6, 0, 1)));
  for (const char* code : {"11HEAD0000H3AVXA", "11HEAD0000H3AVYA", "11HEAD0000H3AVZA"})
    good.push_back(ChannelText(code, "rad/s", 0.001, 0.0, Ramp(6, 0, 1)));
  return good;
}

// The good channels with one channel changed, added or removed, and what
// the error message must mention: the file, the channel or the slot.
struct ChannelErrorCase {
  const char* name;
  void (*spoil)(std::vector<std::string>& channels);
  std::vector<std::string> fragments;
};
void PrintTo(const ChannelErrorCase& error, std::ostream* os) { *os << error.name; }

class IsoMmeChannelErrorTest : public ::testing::TestWithParam<ChannelErrorCase> {};

TEST_P(IsoMmeChannelErrorTest, NamesFileChannelOrSlot) {
  TempDir dir;
  std::vector<std::string> channels = GoodChannels();
  GetParam().spoil(channels);
  WriteFolder(dir / "case", channels);
  ExpectInputError(
      [&] { ReadIsoMmeSignals(dir / "case", test_support::SixAOmegaCg(), LoadChannelMap("default")); },
      GetParam().fragments);
}

INSTANTIATE_TEST_SUITE_P(
    SpoiltChannels, IsoMmeChannelErrorTest,
    ::
        testing::Values(ChannelErrorCase{"NoValueSample",
                                         [](std::vector<std::string>& channels) {
                                           auto values = Ramp(6, 0, 1);
                                           values[3] = "NOVALUE";
                                           channels[2] =
                                               ChannelText("11HEAD0000H3ACZA", "g", 0.001, 0.0, values);
                                         },
                                         {"test.003", "sample 4", "line 12", "NOVALUE"}},
                        ChannelErrorCase{"DeclaredSampleCountDiffers",
                                         [](std::vector<std::string>& channels) {
                                           channels[1] = ChannelText("11HEAD0000H3ACYA", "g", 0.001, 0.0,
                                                                     Ramp(6, 0, 1), 9);
                                         },
                                         {"test.002", "declares 9 samples but the file holds 6"}},
                        ChannelErrorCase{
                            "SamplingIntervalsDiffer",
                            [](std::vector<std::string>& channels) {
                              channels[4] =
                                  ChannelText("11HEAD0000H3AVYA", "rad/s", 0.0005, 0.0, Ramp(6, 0, 1));
                            },
                            {"11HEAD0000H3ACXA", "11HEAD0000H3AVYA", "share the sampling interval"}},
                        ChannelErrorCase{"TimeSpansDoNotOverlap",
                                         [](std::vector<std::string>& channels) {
                                           channels[5] = ChannelText("11HEAD0000H3AVZA", "rad/s", 0.001, 1.0,
                                                                     Ramp(6, 0, 1));
                                         },
                                         {"SN-77", "do not overlap"}},
                        ChannelErrorCase{"SlotMatchedByTwoChannels",
                                         [](std::vector<std::string>& channels) {
                                           channels.push_back(ChannelText("11HEADCG0000ACXP", "g", 0.001, 0.0,
                                                                          Ramp(6, 0, 1)));
                                         },
                                         {"slot \"cg_x\" is matched by two channels", "11HEAD0000H3ACXA",
                                          "11HEADCG0000ACXP"}},
                        ChannelErrorCase{
                            "SlotWithoutChannel",
                            [](std::vector<std::string>& channels) { channels.erase(channels.begin() + 4); },
                            {"no channel matches slot \"ars_y\""}},
                        ChannelErrorCase{"AccelerationUnitOnARateCode",
                                         [](std::vector<std::string>& channels) {
                                           channels[3] = ChannelText("11HEAD0000H3AVXA", "g", 0.001, 0.0,
                                                                     Ramp(6, 0, 1));
                                         },
                                         {"no channel matches slot \"ars_x\""}},
                        ChannelErrorCase{"SampleNotANumber",
                                         [](std::vector<std::string>& channels) {
                                           channels[0] = ChannelText("11HEAD0000H3ACXA", "g", 0.001, 0.0,
                                                                     {"0", "1", "x2", "3", "4", "5"});
                                         },
                                         {"test.001", "sample 3", "\"x2\", not a finite number"}},
                        ChannelErrorCase{"NoSamplingInterval",
                                         [](std::vector<std::string>& channels) {
                                           std::string& text = channels[0];
                                           text.erase(text.find("Sampling interval"),
                                                      text.find("Unit") - text.find("Sampling interval"));
                                         },
                                         {"test.001", "no \"Sampling interval\""}},
                        // Issue 11, item 1: absurd declared counts are refused before anything is allocated.
                        ChannelErrorCase{"DeclaredSampleCountTenToTheTen",
                                         [](std::vector<std::string>& channels) {
                                           channels[1] = ChannelText("11HEAD0000H3ACYA", "g", 0.001, 0.0,
                                                                     Ramp(6, 0, 1), 10'000'000'000L);
                                         },
                                         {"test.002", "11HEAD0000H3ACYA",
                                          "declares 10000000000 samples but the file holds 6"}},
                        ChannelErrorCase{"DeclaredSampleCountTenToTheTwelve",
                                         [](std::vector<std::string>& channels) {
                                           channels[1] = ChannelText("11HEAD0000H3ACYA", "g", 0.001, 0.0,
                                                                     Ramp(6, 0, 1), 1'000'000'000'000L);
                                         },
                                         {"test.002", "11HEAD0000H3ACYA",
                                          "declares 1000000000000 samples but the file holds 6"}},
                        ChannelErrorCase{"DeclaredSampleCountInt64Max",
                                         [](std::vector<std::string>& channels) {
                                           channels[1] =
                                               ChannelText("11HEAD0000H3ACYA", "g", 0.001, 0.0, Ramp(6, 0, 1),
                                                           9'223'372'036'854'775'807L);
                                         },
                                         {"test.002", "11HEAD0000H3ACYA",
                                          "declares 9223372036854775807 samples but the file holds 6"}}),
    test_support::CaseName());

TEST(IsoMmeTest, MissingChannelFilesAreNamed) {
  TempDir dir;
  const auto folder = dir / "nochannel";
  std::filesystem::create_directories(folder);
  test_support::WriteBytes(folder / "a.mme", "Data format :ISO-MME\n");
  ExpectInputError([&] { ReadIsoMme(folder); }, {folder.string(), "no Channel folder"});
  std::filesystem::create_directories(folder / "Channel");
  test_support::WriteBytes(folder / "Channel" / "a.chn", "Number of channels :2\n");
  test_support::WriteBytes(folder / "Channel" / "a.001",
                           ChannelText("11HEAD0000H3ACXA", "g", 0.001, 0.0, Ramp(6, 0, 1)));
  ExpectInputError([&] { ReadIsoMme(folder); }, {"a.002", "channel 2 of 2", "missing"});
}

TEST(IsoMmeTest, MapOrArrayThatDoNotFitTheChannelsAreErrors) {
  TempDir dir;
  const engine::ArrayGeometry array = test_support::SixAOmegaCg();
  const ChannelMap map = LoadChannelMap("default");
  const std::vector<std::string> good = GoodChannels();
  {
    // A map that sends one channel to two slots.
    test_support::WriteBytes(dir / "twice.json", R"({"name": "twice", "slots": {
        "cg_x": {"code": "??HEAD0000??ACX?"}, "cg_y": {"code": "??HEAD0000??ACX?"}, "cg_z": {"code": "??HEAD0000??ACZ?"},
        "ars_x": {"code": "??HEAD0000??AVX?"}, "ars_y": {"code": "??HEAD0000??AVY?"}, "ars_z": {"code": "??HEAD0000??AVZ?"}}})");
    WriteFolder(dir / "twice", good);
    ExpectInputError([&] { ReadIsoMmeSignals(dir / "twice", array, ReadChannelMap(dir / "twice.json")); },
                     {"11HEAD0000H3ACXA", "matched by both slot \"cg_x\" and slot \"cg_y\""});
  }
  WriteFolder(dir / "good", good);
  EXPECT_EQ(ReadIsoMmeSignals(dir / "good", array, map).size(), 6);
  ExpectInputError([&] { ReadIsoMmeSignals(dir / "good", test_support::Denton3222(), map); },
                   {"has no entry for slot \"yarm_z\""});
}

TEST(IsoMmeTest, DerivedExportReadsBack) {
  TempDir dir;
  engine::Kinematics k;
  k.Resize(20);
  for (Eigen::Index i = 0; i < 20; ++i) {
    k.time_s[i] = -0.001 + 0.0005 * static_cast<double>(i);
    for (engine::Series3* s : {&k.omega_body, &k.alpha_body, &k.omega_fixed, &k.alpha_fixed, &k.acc_body,
                               &k.acc_fixed, &k.vel_fixed, &k.pos_fixed, &k.roll_pitch_yaw_rad, &k.dcos_rad})
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
  EXPECT_NEAR(find("11HEAD00GL00ACY0").values[7], 14.0 / engine::kStandardGravity, 1e-12);
  EXPECT_EQ(find("11HEAD00GL00ACY0").unit, "g");
  EXPECT_NEAR(find("11HEAD000000AVZ0").values[5], 15.0, 1e-12);
  EXPECT_NEAR(find("11HEAD00GL00ANX0").values[2], 2.0 * engine::kDegPerRad, 1e-9);
}

}  // namespace
}  // namespace napkin::formats
