// The limits files (config/limits/*.json, app/limits.h, docs/formats.md
// "Limits"): each file's values and its cited source, the docs citing the
// same, and the refusals of a bad --limits (usage) or a malformed file (input).
#include "app/limits.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "common/error.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"

namespace napkin::app {
namespace {

namespace fs = std::filesystem;
const fs::path kConfig = fs::path(NAPKIN_SOURCE_DIR) / "config";

struct Expected {
  const char* preset;
  const char* name;
  std::vector<std::pair<std::string, double>> limits;
  std::vector<std::string> source;  // fragments of the citation
};

TEST(LimitsFiles, ValuesAndSourcesAreThoseOfTheRegulationsAndTheProtocol) {
  const std::vector<Expected> expected = {
      {"fmvss201u", "FMVSS 201U", {{"hic_d", 1000.0}}, {"49 CFR 571.201", "S6.1", "0.75446", "166.4"}},
      {"fmvss208", "FMVSS 208", {{"hic15", 700.0}}, {"49 CFR 571.208", "S6.2(b)", "HIC15", "700"}},
      {"euro-ncap-frontal-head",
       "Euro NCAP frontal head (higher performance)",
       {{"hic15", 500.0}, {"a3ms_g", 72.0}},
       {"Euro NCAP Assessment Protocol - Adult Occupant Protection", "version 8.0.3", "3.1.1"}},
  };
  EXPECT_EQ(LimitPresets(kConfig),
            (std::vector<std::string>{"euro-ncap-frontal-head", "fmvss201u", "fmvss208"}));
  const std::string docs = test_support::ReadText(fs::path(NAPKIN_SOURCE_DIR) / "docs" / "formats.md");
  for (const Expected& e : expected) {
    const LimitSet set = LoadLimits(e.preset, kConfig);
    EXPECT_EQ(set.name, e.name);
    ASSERT_EQ(set.limits.size(), e.limits.size()) << e.preset;
    for (std::size_t i = 0; i < e.limits.size(); ++i) {
      EXPECT_EQ(set.limits[i].metric, e.limits[i].first) << e.preset;
      EXPECT_EQ(set.limits[i].max, e.limits[i].second) << e.preset;
    }
    for (const std::string& fragment : e.source)
      EXPECT_NE(set.source.find(fragment), std::string::npos) << e.preset << ": " << fragment;
    EXPECT_FALSE(set.url.empty());
    // The docs' table names the preset and cites the same source.
    EXPECT_NE(docs.find("| `" + std::string(e.preset) + "` |"), std::string::npos) << e.preset;
    EXPECT_NE(docs.find(e.source.front()), std::string::npos) << e.source.front();
  }
  // HIC(d) is the FMVSS 201 formula of the stored field (engine: 0.75446 HIC36 + 166.4).
  EXPECT_NE(docs.find("HIC(d) ≤ 1000, HIC(d) = 0.75446 HIC36 + 166.4"), std::string::npos);
}

TEST(LimitsFiles, UnknownNamesAreUsageErrorsAndMalformedFilesInputErrors) {
  try {
    LoadLimits("fmvss999", kConfig);
    FAIL() << "no error";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("--limits 'fmvss999' is neither a file nor a preset"),
              std::string::npos);
  }
  test_support::TempDir dir;
  const auto expect_input_error = [&](const std::string& text, const std::string& fragment) {
    const fs::path file = dir / "bad.json";
    test_support::WriteText(file, text);
    try {
      LoadLimits(file.string(), kConfig);
      ADD_FAILURE() << "no error for " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
    }
  };
  const std::string head = R"({"name":"x","title":"t","applies_to":"a","source":"s","url":"u",)";
  expect_input_error("{", "is not valid JSON");
  expect_input_error(head + R"("limits":[]})", "\"limits\" must be a non-empty array");
  expect_input_error(head + R"("limits":[{"metric":"hic99","max":1,"requirement":"r"}]})",
                     "metric 'hic99' is not a field of `napkin query criteria`");
  expect_input_error(head + R"("limits":[{"metric":"hic15","max":-1,"requirement":"r"}]})",
                     "must be a positive number");
  expect_input_error(R"({"name":"x","limits":[]})", "\"title\" must be a non-empty string");
}

// A limit is finite and plausible, and a key the file may not have is refused naming it (issue 42,
// point 13: "max": 1e308 printed margins of +inf %, and "colour" was accepted silently).
TEST(LimitsFiles, ImplausibleLimitsAndUnknownKeysAreRefusedNamingThem) {
  test_support::TempDir dir;
  const auto error_of = [&](const std::string& text) -> std::string {
    const fs::path file = dir / "bad.json";
    test_support::WriteText(file, text);
    try {
      LoadLimits(file.string(), kConfig);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  const std::string file = (dir / "bad.json").string();
  const std::string head = R"({"name":"x","title":"t","applies_to":"a","source":"s","url":"u",)";
  EXPECT_EQ(error_of(head + R"("limits":[{"metric":"hic15","max":1e308,"requirement":"r"}]})"),
            "limits file " + file +
                ": the \"max\" of metric 'hic15', 1e+308, is not a plausible limit (it must be from 1e-06 to "
                "1e+06).");
  EXPECT_NE(error_of(head + R"("limits":[{"metric":"hic15","max":1e-300,"requirement":"r"}]})")
                .find("is not a plausible limit"),
            std::string::npos);
  EXPECT_EQ(
      error_of(head + R"("colour":"red","limits":[{"metric":"hic15","max":700,"requirement":"r"}]})"),
      "limits file " + file +
          ": the file has the unknown key \"colour\" (it may give name, title, applies_to, source, url, "
          "limits).");
  EXPECT_EQ(error_of(head + R"("limits":[{"metric":"hic15","maximum":700,"max":700,"requirement":"r"}]})"),
            "limits file " + file +
                ": a limit has the unknown key \"maximum\" (it may give metric, max, requirement).");
  // The presets and a plausible file still load.
  EXPECT_EQ(error_of(head + R"("limits":[{"metric":"hic15","max":700,"requirement":"r"}]})"), "no error");
}

}  // namespace
}  // namespace napkin::app
