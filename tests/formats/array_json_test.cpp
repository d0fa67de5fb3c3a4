#include "formats/array_json.h"

#include <gtest/gtest.h>

#include <fstream>
#include <numbers>

#include "common/error.h"
#include "engine/units.h"
#include "tests/support/reference_arrays.h"
#include "tests/support/test_support.h"

namespace napkin::formats {
namespace {

using test_support::TempDir;

void ExpectSameArray(const engine::ArrayGeometry& expected, const engine::ArrayGeometry& actual) {
  ASSERT_EQ(expected.sensors.size(), actual.sensors.size()) << expected.name;
  for (std::size_t i = 0; i < expected.sensors.size(); ++i) {
    const engine::Sensor& e = expected.sensors[i];
    const engine::Sensor& a = actual.sensors[i];
    SCOPED_TRACE(expected.name + " sensor " + e.slot);
    EXPECT_EQ(e.slot, a.slot);
    EXPECT_EQ(e.kind, a.kind);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(e.position_body_m[c], a.position_body_m[c], 1e-12);
      EXPECT_NEAR(e.axis_body[c], a.axis_body[c], 1e-15);
    }
    EXPECT_EQ(e.unit, a.unit);
    EXPECT_DOUBLE_EQ(e.si_per_unit, a.si_per_unit);
  }
}

std::filesystem::path WriteText(const TempDir& dir, const std::string& name, const std::string& text) {
  std::filesystem::path path = dir / name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// Expects ReadArrayJson(path) to throw InputError whose message names the
// file and contains `fragment`.
void ExpectArrayError(const std::filesystem::path& path, const std::string& fragment) {
  try {
    ReadArrayJson(path);
    FAIL() << "no error for " << path;
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    EXPECT_NE(message.find(fragment), std::string::npos) << message;
    EXPECT_EQ(message.back(), '.') << message;
  }
}

TEST(ArrayJsonTest, PresetsEqualTheReportGeometries) {
  const std::filesystem::path dir = test_support::SourceDir() / "config" / "arrays";
  ExpectSameArray(test_support::Ideal3222(), ReadArrayJson(dir / "ideal-3222.json"));
  ExpectSameArray(test_support::VolpeTable42(), ReadArrayJson(dir / "volpe-table4-2.json"));
  ExpectSameArray(test_support::Denton3222(), ReadArrayJson(dir / "denton-3222.json"));
  ExpectSameArray(test_support::SixAOmegaCg(), ReadArrayJson(dir / "6aw-cg.json"));
  ExpectSameArray(test_support::NapArs12(), ReadArrayJson(dir / "nap-ars-12.json"));
  ExpectSameArray(test_support::ThreeACg(), ReadArrayJson(dir / "3a-cg.json"));
  EXPECT_FALSE(engine::DeterminesRotation(ReadArrayJson(dir / "3a-cg.json")));  // acceleration only
  for (const char* name : {"ideal-3222", "volpe-table4-2", "denton-3222", "6aw-cg", "nap-ars-12", "3a-cg"})
    EXPECT_EQ(ReadArrayJson(dir / (std::string(name) + ".json")).name, name);
}

TEST(ArrayJsonTest, LoadArrayFindsPresetsByName) {
  ExpectSameArray(test_support::Denton3222(), LoadArray("denton-3222"));
  EXPECT_THROW(LoadArray("no-such-array"), InputError);
}

TEST(ArrayJsonTest, RoundTripInEveryLengthUnit) {
  TempDir dir;
  for (const char* unit : {"in", "mm", "m"}) {
    engine::ArrayGeometry array = test_support::NapArs12();
    array.sensors[4].unit = "m/s^2";
    array.sensors[4].si_per_unit = 1.0;
    array.sensors[10].unit = "deg/s";
    array.sensors[10].si_per_unit = std::numbers::pi / 180.0;
    const std::filesystem::path path = dir / (std::string("array-") + unit + ".json");
    WriteArrayJson(array, path, unit);
    ExpectSameArray(array, ReadArrayJson(path));
  }
}

TEST(ArrayJsonTest, AxesAreNormalisedAndUnitsConverted) {
  TempDir dir;
  const auto path = WriteText(dir, "a.json", R"({"length_unit": "mm", "sensors": [
      {"slot": "a", "type": "linear", "position": [10, 20, 30], "axis": [3, 0, 4], "unit": "m/s^2"},
      {"slot": "w", "type": "angular_rate", "axis": [0, 0, -2], "unit": "deg/s"},
      {"slot": "b", "type": "linear", "position": [0, 0, 0], "axis": [0, 1, 0], "unit": "g"},
      {"slot": "c", "type": "linear", "position": [0, 0, 0], "axis": [0, 0, 1], "unit": "g"},
      {"slot": "u", "type": "angular_rate", "axis": [1, 0, 0], "unit": "rad/s"},
      {"slot": "v", "type": "angular_rate", "axis": [0, 1, 0], "unit": "rad/s"}]})");
  const engine::ArrayGeometry array = ReadArrayJson(path);
  EXPECT_EQ(array.name, "a");
  ASSERT_EQ(array.sensors.size(), 6u);
  EXPECT_NEAR(array.sensors[0].position_body_m.x(), 0.010, 1e-15);
  EXPECT_NEAR(array.sensors[0].position_body_m.z(), 0.030, 1e-15);
  EXPECT_NEAR(array.sensors[0].axis_body.x(), 0.6, 1e-15);
  EXPECT_NEAR(array.sensors[0].axis_body.z(), 0.8, 1e-15);
  EXPECT_EQ(array.sensors[0].si_per_unit, 1.0);
  EXPECT_EQ(array.sensors[1].kind, engine::SensorKind::kAngularRate);
  EXPECT_NEAR(array.sensors[1].axis_body.z(), -1.0, 1e-15);
  EXPECT_NEAR(array.sensors[1].si_per_unit, std::numbers::pi / 180.0, 1e-18);
  EXPECT_TRUE(array.sensors[1].position_body_m.isZero());
}

TEST(ArrayJsonTest, BadDefinitionsNameFileAndSlot) {
  TempDir dir;
  const std::string ok_sensor =
      R"({"slot": "cg_x", "type": "linear", "position": [0,0,0], "axis": [1,0,0], "unit": "g"})";
  auto array_with = [&](const std::string& sensor) {
    return R"({"length_unit": "in", "sensors": [)" + ok_sensor + "," + sensor + "]}";
  };
  ExpectArrayError(WriteText(dir, "syntax.json", "{\"length_unit\": "), "not valid JSON");
  ExpectArrayError(WriteText(dir, "root.json", "[1, 2]"), "must be a JSON object");
  ExpectArrayError(WriteText(dir, "nounit.json", R"({"sensors": []})"), "length_unit");
  ExpectArrayError(WriteText(dir, "badlen.json", R"({"length_unit": "furlong", "sensors": []})"),
                   "unknown length_unit \"furlong\"");
  ExpectArrayError(WriteText(dir, "nosensors.json", R"({"length_unit": "in"})"), "no \"sensors\"");
  ExpectArrayError(WriteText(dir, "empty.json", R"({"length_unit": "in", "sensors": []})"), "no sensors");
  ExpectArrayError(WriteText(dir, "type.json",
                             array_with(R"({"slot": "q", "type": "gyro", "axis": [1,0,0], "unit": "g"})")),
                   "sensor 2 (slot \"q\") has unknown type \"gyro\"");
  ExpectArrayError(
      WriteText(
          dir, "unit.json",
          array_with(
              R"({"slot": "q", "type": "linear", "position": [0,0,0], "axis": [1,0,0], "unit": "rad/s"})")),
      "slot \"q\") has unknown unit \"rad/s\"");
  ExpectArrayError(
      WriteText(dir, "rateunit.json",
                array_with(R"({"slot": "w", "type": "angular_rate", "axis": [1,0,0], "unit": "g"})")),
      "slot \"w\") has unknown unit \"g\"");
  ExpectArrayError(
      WriteText(dir, "noaxis.json",
                array_with(R"({"slot": "q", "type": "linear", "position": [0,0,0], "unit": "g"})")),
      "slot \"q\") has no \"axis\"");
  ExpectArrayError(WriteText(dir, "nopos.json",
                             array_with(R"({"slot": "q", "type": "linear", "axis": [1,0,0], "unit": "g"})")),
                   "slot \"q\") has no \"position\"");
  ExpectArrayError(
      WriteText(dir, "zeroaxis.json",
                array_with(
                    R"({"slot": "q", "type": "linear", "position": [0,0,0], "axis": [0,0,0], "unit": "g"})")),
      "slot \"q\") has a zero axis");
  ExpectArrayError(
      WriteText(
          dir, "axislen.json",
          array_with(R"({"slot": "q", "type": "linear", "position": [0,0,0], "axis": [1,0], "unit": "g"})")),
      "\"axis\" must be an array of three numbers");
  ExpectArrayError(
      WriteText(
          dir, "axistype.json",
          array_with(
              R"({"slot": "q", "type": "linear", "position": [0,"a",0], "axis": [1,0,0], "unit": "g"})")),
      "\"position\" must be an array of three numbers");
  ExpectArrayError(
      WriteText(
          dir, "slottype.json",
          array_with(R"({"slot": 7, "type": "linear", "position": [0,0,0], "axis": [1,0,0], "unit": "g"})")),
      "sensor 2: \"slot\" must be a string, not a number");
  ExpectArrayError(WriteText(dir, "dup.json", array_with(ok_sensor)),
                   "sensor 2 (slot \"cg_x\") duplicates an earlier slot");
  ExpectArrayError(WriteText(dir, "noslot.json", array_with(R"({"type": "linear"})")),
                   "sensor 2 has no \"slot\"");
}

}  // namespace
}  // namespace napkin::formats
