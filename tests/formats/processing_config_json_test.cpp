// Processing configuration JSON: canonical form, round trips, partial
// files, and errors that name the file and the key.
#include "formats/processing_config_json.h"

#include <gtest/gtest.h>

#include <fstream>
#include <ostream>
#include <string>
#include <vector>

#include "common/error.h"
#include "tests/support/named_cases.h"
#include "tests/support/test_support.h"

namespace napkin::formats {
namespace {

using nlohmann::json;

std::string ErrorOf(const json& document) {
  try {
    ParseProcessingConfig(document, "test.json");
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

// Every field away from its default. Settings that exclude each other
// (ProcessingConfig::Check refuses a setting another one would ignore) are
// split between this configuration and SeedWindowConfig().
engine::ProcessingConfig NonDefaultConfig() {
  engine::ProcessingConfig config;
  config.filter.variant = engine::CfcVariant::kIso6487;
  config.filter.linear_cfc = 600.0;
  config.filter.angular_rate_cfc.reset();
  config.filter.padding_s = 0.025;
  config.bias.auto_min_pre_impact_s = 0.002;  // mode "auto" (SeedWindowConfig has "window")
  config.time.shift_s = 0.0123;
  config.time.start_s = -0.005;
  config.time.end_s.reset();
  config.gravity.compensate = true;
  config.gravity.g_fixed_mps2 = Eigen::Vector3d(0.1, -0.2, 9.81);
  config.hic.from_time_zero = true;
  config.bric.critical_radps = Eigen::Vector3d(1.0 / 3.0, 2.0, 3.5);
  config.screening.residual_limit_g = 1.5;
  config.screening.spike_size_g = 33.0;
  config.screening.spike_size_radps = 7.0;
  config.screening.saturation_run_samples = 9;
  config.screening.bias_limit_g = 0.75;
  config.screening.bias_limit_radps = 0.125;
  config.storage.derived_channels = engine::DerivedStorage::kNone;
  return config;
}

// The seed solver (no gravity compensation) and a bias window.
engine::ProcessingConfig SeedWindowConfig() {
  engine::ProcessingConfig config = NonDefaultConfig();
  config.solver = engine::SolverKind::kSeed;
  config.gravity = {};
  config.bias.mode = engine::BiasMode::kWindow;
  config.bias.window_start_s = -0.02;
  config.bias.window_end_s = -0.001;
  config.bias.auto_min_pre_impact_s = engine::BiasConfig{}.auto_min_pre_impact_s;
  return config;
}

void ExpectSortedKeysEverywhere(const json& value) {
  if (!value.is_object()) return;
  std::string previous;
  for (const auto& [key, child] : value.items()) {
    EXPECT_LT(previous, key);
    previous = key;
    ExpectSortedKeysEverywhere(child);
  }
}

TEST(ProcessingConfigJson, CanonicalFormHasEveryFieldSorted) {
  const json canonical = ProcessingConfigToJson(engine::ProcessingConfig{});
  ExpectSortedKeysEverywhere(canonical);
  EXPECT_EQ(canonical.size(), 9u);
  for (const char* key :
       {"solver", "filter", "bias", "time", "gravity", "hic", "bric", "screening", "plausibility"})
    EXPECT_TRUE(canonical.contains(key)) << key;
  EXPECT_EQ(canonical["filter"].size(), 4u);
  EXPECT_EQ(canonical["bias"].size(), 3u);
  EXPECT_EQ(canonical["time"].size(), 3u);
  EXPECT_TRUE(canonical["time"]["start_s"].is_null());
  EXPECT_EQ(canonical["screening"].size(), 6u);
  EXPECT_EQ(canonical["plausibility"].size(), 4u);
  EXPECT_EQ(canonical["plausibility"]["max_acceleration_g"], 2000.0);
  EXPECT_EQ(canonical["filter"]["linear_cfc"], 1000.0);
  EXPECT_EQ(canonical["gravity"]["g_fixed"], json::array({0.0, 0.0, 9.80665}));
  // Compact dump starts with the first sorted key.
  EXPECT_EQ(CanonicalProcessingConfig(engine::ProcessingConfig{}).rfind("{\"bias\":", 0), 0u);
}

TEST(ProcessingConfigJson, RoundTripIsExactAndCanonical) {
  for (const engine::ProcessingConfig& config : {NonDefaultConfig(), SeedWindowConfig()}) {
    const json canonical = ProcessingConfigToJson(config);
    const engine::ProcessingConfig parsed = ParseProcessingConfig(canonical, "round trip");
    EXPECT_EQ(CanonicalProcessingConfig(parsed), CanonicalProcessingConfig(config));
    EXPECT_EQ(parsed.bric.critical_radps, config.bric.critical_radps);  // 1/3 survives bit for bit
    EXPECT_EQ(parsed.time.start_s, config.time.start_s);
    EXPECT_FALSE(parsed.time.end_s.has_value());
    EXPECT_FALSE(parsed.filter.angular_rate_cfc.has_value());
    EXPECT_EQ(canonical["filter"]["angular_rate_cfc"], "none");
    // ADL hooks.
    const json via_adl = config;
    EXPECT_EQ(via_adl, canonical);
    EXPECT_EQ(CanonicalProcessingConfig(via_adl.get<engine::ProcessingConfig>()),
              CanonicalProcessingConfig(config));
    // A different configuration has a different canonical dump.
    engine::ProcessingConfig other = config;
    other.hic.from_time_zero = false;
    EXPECT_NE(CanonicalProcessingConfig(other), CanonicalProcessingConfig(config));
  }
}

TEST(ProcessingConfigJson, PartialDocumentsKeepDefaultsAndIntegersEqualDoubles) {
  const engine::ProcessingConfig parsed = ParseProcessingConfig(
      json::parse(R"({"filter": {"linear_cfc": "none"}, "name": "x", "description": "y"})"), "partial");
  engine::ProcessingConfig expected;
  expected.filter.linear_cfc.reset();
  EXPECT_EQ(CanonicalProcessingConfig(parsed), CanonicalProcessingConfig(expected));
  // 1000 and 1000.0 are the same configuration.
  const auto integer = ParseProcessingConfig(json::parse(R"({"filter": {"linear_cfc": 1000}})"), "a");
  const auto real = ParseProcessingConfig(json::parse(R"({"filter": {"linear_cfc": 1000.0}})"), "b");
  EXPECT_EQ(CanonicalProcessingConfig(integer), CanonicalProcessingConfig(real));
  EXPECT_EQ(CanonicalProcessingConfig(integer), CanonicalProcessingConfig(engine::ProcessingConfig{}));
}

// A configuration document that is refused, and what the message must
// mention: the source ("test.json") and the key, or what would be accepted.
struct ConfigErrorCase {
  const char* name;
  const char* document;
  std::vector<const char*> parts;
};
void PrintTo(const ConfigErrorCase& error, std::ostream* os) { *os << error.document; }

class ProcessingConfigErrorTest : public ::testing::TestWithParam<ConfigErrorCase> {};

TEST_P(ProcessingConfigErrorTest, NamesTheSourceAndTheKey) {
  const std::string message = ErrorOf(json::parse(GetParam().document));
  ASSERT_FALSE(message.empty());
  for (const char* part : GetParam().parts) EXPECT_NE(message.find(part), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(
    BadDocuments, ProcessingConfigErrorTest,
    ::testing::Values(
        ConfigErrorCase{
            "unknown_filter_key", R"({"filter": {"linear_cfx": 1000}})", {"test.json", "filter.linear_cfx"}},
        ConfigErrorCase{"unknown_section", R"({"hics": {}})", {"test.json", "hics"}},
        ConfigErrorCase{"number_for_boolean",
                        R"({"hic": {"from_time_zero": 1}})",
                        {"hic.from_time_zero", "true or false"}},
        ConfigErrorCase{
            "negative_cfc", R"({"filter": {"linear_cfc": -1}})", {"test.json", "filter.linear_cfc"}},
        ConfigErrorCase{
            "cfc_off_for_none", R"({"filter": {"linear_cfc": "off"}})", {"filter.linear_cfc", "none"}},
        ConfigErrorCase{
            "unknown_bias_mode", R"({"bias": {"mode": "sometimes"}})", {"bias.mode", "\"window\""}},
        ConfigErrorCase{"unknown_bias_key", R"({"bias": {"window_s": [0.0]}})", {"bias.window_s"}},
        ConfigErrorCase{
            "text_in_bric_vector", R"({"bric": {"critical_radps": [1, 2, "3"]}})", {"bric.critical_radps"}},
        ConfigErrorCase{
            "zero_in_bric_vector", R"({"bric": {"critical_radps": [1, 0, 3]}})", {"bric.critical_radps[1]"}},
        ConfigErrorCase{"fraction_for_integer",
                        R"({"screening": {"saturation_run_samples": 2.5}})",
                        {"screening.saturation_run_samples", "integer"}},
        ConfigErrorCase{"text_for_time", R"({"time": {"start_s": "0"}})", {"time.start_s"}},
        ConfigErrorCase{"array_for_section", R"({"gravity": []})", {"gravity", "object"}},
        ConfigErrorCase{"unknown_solver", R"({"solver": "fast"})", {"solver", "\"exact\""}},
        ConfigErrorCase{"unknown_derived_storage",
                        R"({"storage": {"derived_channels": "float16"}})",
                        {"test.json: ", "storage.derived_channels", "\"float64\", \"float32\", \"none\""}},
        ConfigErrorCase{
            "unknown_storage_key", R"({"storage": {"kinematics": "none"}})", {"storage.kinematics"}},
        ConfigErrorCase{"array_for_document", R"([1, 2])", {"test.json", "object"}},
        // Settings another one would silently ignore are refused (issue 8).
        ConfigErrorCase{"seed_solver_with_gravity_compensation",
                        R"({"solver": "seed", "gravity": {"compensate": true}})",
                        {"test.json: ", "gravity.compensate", "seed solver", "\"exact\""}},
        ConfigErrorCase{"bias_window_without_window_mode",
                        R"({"bias": {"mode": "none", "window_s": [-0.02, 0.0]}})",
                        {"test.json: ", "bias.window_s", "ignored", "\"none\""}}),
    test_support::CaseName());

TEST(ProcessingConfigJson, DefaultPresetIsTheDefaultConfiguration) {
  const auto path = test_support::SourceDir() / "config" / "processing" / "default.json";
  const engine::ProcessingConfig preset = ReadProcessingConfig(path);
  EXPECT_EQ(CanonicalProcessingConfig(preset), CanonicalProcessingConfig(engine::ProcessingConfig{}));
}

TEST(ProcessingConfigJson, FileErrorsNameTheFile) {
  test_support::TempDir dir;
  EXPECT_THROW(ReadProcessingConfig(dir / "missing.json"), InputError);
  {
    std::ofstream(dir / "broken.json") << "{\"filter\": ";
    std::ofstream(dir / "bad_key.json") << R"({"bias": {"mode": "auto", "windows": [0, 1]}})";
  }
  for (const char* name : {"missing.json", "broken.json", "bad_key.json"}) {
    try {
      ReadProcessingConfig(dir / name);
      ADD_FAILURE() << name;
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find(name), std::string::npos) << error.what();
    }
  }
  try {
    ReadProcessingConfig(dir / "bad_key.json");
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("bias.windows"), std::string::npos) << error.what();
  }
}

// storage.derived_channels (docs/formats.md "Derived-channel storage"): each
// name reads back, the default float32 leaves the canonical form (and hash)
// of earlier configurations alone, and each choice has its own canonical dump.
TEST(ProcessingConfigJson, DerivedStorageChoicesAreDistinctAndTheDefaultIsFloat32) {
  EXPECT_EQ(engine::ProcessingConfig{}.storage.derived_channels, engine::DerivedStorage::kFloat32);
  const std::string default_dump = CanonicalProcessingConfig(engine::ProcessingConfig{});
  EXPECT_EQ(default_dump.find("storage"), std::string::npos);
  std::vector<std::string> dumps;
  for (const engine::DerivedStorage storage : engine::kDerivedStorages) {
    const std::string name = engine::NameOf(storage);
    EXPECT_EQ(engine::ParseName<engine::DerivedStorage>(name), storage) << name;
    const engine::ProcessingConfig parsed =
        ParseProcessingConfig(json{{"storage", {{"derived_channels", name}}}}, "storage");
    EXPECT_EQ(parsed.storage.derived_channels, storage) << name;
    const json canonical = ProcessingConfigToJson(parsed);
    if (storage == engine::DerivedStorage::kFloat32) {
      EXPECT_FALSE(canonical.contains("storage"));
      EXPECT_EQ(CanonicalProcessingConfig(parsed), default_dump);
    } else {
      EXPECT_EQ(canonical.at("storage"), (json{{"derived_channels", name}}));
      engine::ProcessingConfig expected;
      expected.storage.derived_channels = storage;
      EXPECT_EQ(CanonicalProcessingConfig(ParseProcessingConfig(canonical, "round trip")),
                CanonicalProcessingConfig(expected));
    }
    dumps.push_back(CanonicalProcessingConfig(parsed));
  }
  EXPECT_NE(dumps[0], dumps[1]);
  EXPECT_NE(dumps[0], dumps[2]);
  EXPECT_NE(dumps[1], dumps[2]);
  EXPECT_FALSE(engine::ParseName<engine::DerivedStorage>("Float32").has_value());
}

}  // namespace
}  // namespace napkin::formats
