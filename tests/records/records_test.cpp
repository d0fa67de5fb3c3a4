// Engine types <-> catalogue records: arrays read back bit-exact, config
// records identify the canonical configuration, slot units come from the
// array.
#include <gtest/gtest.h>

#include "common/error.h"
#include "formats/array_json.h"
#include "formats/processing_config_json.h"
#include "records/array_record.h"
#include "records/config_record.h"
#include "records/test_record.h"
#include "util/sha256.h"

namespace napkin::records {
namespace {

TEST(ArrayRecordTest, PresetsReadBackBitExact) {
  for (const char* preset : {"ideal-3222", "denton-3222", "nap-ars-12", "6aw-cg", "volpe-table4-2"}) {
    const engine::ArrayGeometry array = formats::LoadArray(preset);
    const db::ArrayRow record = MakeArrayRecord(array);
    EXPECT_EQ(record.name, array.name);
    EXPECT_EQ(record.definition_hash, util::Sha256Hex(record.definition_json));
    const engine::ArrayGeometry decoded = DecodeArrayRecord(record);
    ASSERT_EQ(decoded.sensors.size(), array.sensors.size()) << preset;
    for (std::size_t i = 0; i < array.sensors.size(); ++i) {
      EXPECT_EQ(decoded.sensors[i].slot, array.sensors[i].slot) << preset;
      EXPECT_EQ(decoded.sensors[i].unit, array.sensors[i].unit) << preset;
      // Exact equality: the record is in metres, the engine's unit.
      EXPECT_EQ(decoded.sensors[i].position_body_m, array.sensors[i].position_body_m) << preset << " " << i;
      EXPECT_EQ(decoded.sensors[i].axis_body, array.sensors[i].axis_body) << preset << " " << i;
    }
    // The record of the decoded array is the same record.
    EXPECT_EQ(MakeArrayRecord(decoded).definition_json, record.definition_json) << preset;
  }
}

TEST(ArrayRecordTest, BadDefinitionsNameTheArray) {
  const db::ArrayRow not_json{{}, "x", "{", "h"};
  try {
    DecodeArrayRecord(not_json);
    ADD_FAILURE() << "malformed JSON was accepted";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "array 'x' of the catalogue is not valid JSON.");
  }
  const db::ArrayRow no_sensors{{}, "y", R"({"name":"y","length_unit":"m","sensors":[]})", "h"};
  try {
    DecodeArrayRecord(no_sensors);
    ADD_FAILURE() << "an array without sensors was accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("array 'y' of the catalogue"), std::string::npos)
        << error.what();
  }
}

TEST(ConfigRecordTest, RecordIsTheCanonicalJsonAndItsHash) {
  engine::ProcessingConfig config;
  config.filter.padding_s = 0.02;
  const db::ConfigRow record = MakeConfigRecord(config, "mine");
  EXPECT_EQ(record.name, "mine");
  EXPECT_EQ(record.config_json, formats::CanonicalProcessingConfig(config));
  EXPECT_EQ(record.config_hash, util::Sha256Hex(record.config_json));

  const ResolvedConfig preset = ResolveConfig("");
  EXPECT_EQ(preset.record.name, "default");
  EXPECT_EQ(preset.record.config_json, formats::CanonicalProcessingConfig(preset.config));
  EXPECT_EQ(preset.record.config_hash, MakeConfigRecord(preset.config, "other").config_hash);
  EXPECT_EQ(ResolveConfig("default").record.config_hash, preset.record.config_hash);
}

TEST(ConfigRecordTest, DecodesBackToTheSameCanonicalConfig) {
  engine::ProcessingConfig config;
  config.filter.padding_s = 0.0123456789012345;
  config.screening.residual_limit_g = 4.321098765432109;
  config.storage.derived_channels = engine::DerivedStorage::kNone;
  const db::ConfigRow record = MakeConfigRecord(config, "unusual");
  const engine::ProcessingConfig decoded = DecodeConfigRecord(record);
  EXPECT_EQ(decoded.filter.padding_s, config.filter.padding_s);
  EXPECT_EQ(decoded.screening.residual_limit_g, config.screening.residual_limit_g);
  EXPECT_EQ(decoded.storage.derived_channels, engine::DerivedStorage::kNone);
  EXPECT_EQ(MakeConfigRecord(decoded, "unusual").config_json, record.config_json);
}

TEST(ConfigRecordTest, BadStoredConfigsNameTheConfig) {
  db::ConfigRow record;
  record.name = "broken";
  record.config_json = "{";
  try {
    DecodeConfigRecord(record);
    FAIL() << "malformed JSON decoded";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()), "config 'broken' of the catalogue is not valid JSON.");
  }
  record.config_json = R"({"filter": {"padding_s": -1}})";
  try {
    DecodeConfigRecord(record);
    FAIL() << "a negative padding decoded";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("config 'broken' of the catalogue"), std::string::npos)
        << error.what();
  }
}

TEST(TestRecordTest, SlotUnitsComeFromTheArray) {
  const engine::ArrayGeometry array = formats::LoadArray("ideal-3222");
  std::vector<std::string> slots;
  std::vector<std::string> expected;
  for (auto it = array.sensors.rbegin(); it != array.sensors.rend(); ++it) {
    slots.push_back(it->slot);
    expected.push_back(it->unit);
  }
  EXPECT_EQ(SlotUnits(array, slots), expected);
  try {
    SlotUnits(array, {slots[0], "nowhere"});
    ADD_FAILURE() << "an unknown slot was accepted";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()), "channel 'nowhere' is not a slot of array '" + array.name + "'.");
  }
}

}  // namespace
}  // namespace napkin::records
