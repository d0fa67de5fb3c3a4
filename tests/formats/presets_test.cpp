// formats/presets.h: every kind of preset is resolved one way, and the same
// mistake (a name that is neither a file nor a preset) gives the same
// sentence and the same error type (a usage error, exit status 2) for each
// kind (docs/formats.md "Presets").
#include "formats/presets.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "common/error.h"
#include "formats/array_json.h"
#include "formats/channel_map.h"
#include "tests/support/test_support.h"

namespace napkin::formats {
namespace {

namespace fs = std::filesystem;
using test_support::TempDir;

void WritePresetFile(const fs::path& path) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << "{}\n";
}

// A configuration folder holding, for each kind, presets "b-second" and
// "a-first" (written out of order) and a file that is not a preset (notes.txt).
class PresetsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const PresetKind kind : PresetKinds()) {
      const fs::path folder = config_.path() / std::string(PresetFolder(kind));
      WritePresetFile(folder / "b-second.json");
      WritePresetFile(folder / "a-first.json");
      WritePresetFile(folder / "notes.txt");
    }
  }

  // The sentence and whether it was an UnknownPresetError (a UsageError).
  static std::string UnknownSentence(PresetKind kind, const std::string& name, const fs::path& config) {
    try {
      ResolvePreset(kind, name, config);
    } catch (const UnknownPresetError& error) {
      const UsageError& usage = error;  // exit status 2 (app/failure.h sorts UsageError as kUsage)
      return usage.what();
    }
    ADD_FAILURE() << "no UnknownPresetError for \"" << name << "\"";
    return "";
  }

  TempDir config_;
};

TEST_F(PresetsTest, KindsNameTheirFolders) {
  std::vector<std::pair<std::string, std::string>> kinds;
  for (const PresetKind kind : PresetKinds())
    kinds.emplace_back(std::string(PresetKindName(kind)), std::string(PresetFolder(kind)));
  const std::vector<std::pair<std::string, std::string>> expected = {{"array", "arrays"},
                                                                     {"processing", "processing"},
                                                                     {"limits", "limits"},
                                                                     {"channel-map", "channel-maps"}};
  EXPECT_EQ(kinds, expected);
  for (const PresetKind kind : PresetKinds()) EXPECT_EQ(PresetKindNamed(PresetKindName(kind)), kind);
  try {
    PresetKindNamed("arrays");
    FAIL() << "no error";
  } catch (const UsageError& error) {
    EXPECT_STREQ(error.what(),
                 "preset kind \"arrays\" is not one of array, processing, limits, channel-map.");
  }
}

TEST_F(PresetsTest, NamesArePresetsAndPathsAreFiles) {
  const fs::path own_file = config_.path() / "mine.json";
  WritePresetFile(own_file);
  for (const PresetKind kind : PresetKinds()) {
    SCOPED_TRACE(std::string(PresetKindName(kind)));
    const fs::path folder = config_.path() / std::string(PresetFolder(kind));
    EXPECT_EQ(PresetNames(kind, config_.path()), (std::vector<std::string>{"a-first", "b-second"}));
    EXPECT_EQ(ResolvePreset(kind, "b-second", config_.path()), folder / "b-second.json");
    EXPECT_EQ(ResolvePreset(kind, own_file.string(), config_.path()), own_file);
  }
}

TEST_F(PresetsTest, TheSameMistakeIsTheSameSentenceForEveryKind) {
  for (const PresetKind kind : PresetKinds()) {
    SCOPED_TRACE(std::string(PresetKindName(kind)));
    const std::string folder = (config_.path() / std::string(PresetFolder(kind))).string();
    const std::string list = " (presets: a-first, b-second).";
    EXPECT_EQ(UnknownSentence(kind, "nope", config_.path()),
              "\"nope\" is neither a file nor a preset in " + folder + list);
    // A preset's name with its extension, a path that is not there, a name
    // reaching out of the folder, a non-preset file of the folder, nothing.
    EXPECT_EQ(UnknownSentence(kind, "a-first.json", config_.path()),
              "\"a-first.json\" is neither a file nor a preset in " + folder + list);
    EXPECT_EQ(UnknownSentence(kind, "../arrays/a-first", config_.path()),
              "\"../arrays/a-first\" is neither a file nor a preset in " + folder + list);
    EXPECT_EQ(UnknownSentence(kind, "notes", config_.path()),
              "\"notes\" is neither a file nor a preset in " + folder + list);
    EXPECT_EQ(UnknownSentence(kind, "", config_.path()),
              "\"\" is neither a file nor a preset in " + folder + list);
    // A folder is not a file.
    EXPECT_EQ(UnknownSentence(kind, folder, config_.path()),
              "\"" + folder + "\" is neither a file nor a preset in " + folder + list);
  }
}

TEST_F(PresetsTest, AMissingFolderListsNoPresets) {
  const TempDir empty;
  EXPECT_TRUE(PresetNames(PresetKind::kLimits, empty.path()).empty());
  EXPECT_EQ(UnknownSentence(PresetKind::kLimits, "fmvss208", empty.path()),
            "\"fmvss208\" is neither a file nor a preset in " + (empty.path() / "limits").string() +
                " (presets: ).");
}

// The readers of formats/ that take a name (LoadArray, LoadChannelMap) say
// the resolver's sentence, in the default configuration folder.
TEST(PresetReaders, LoadArrayAndLoadChannelMapSayTheOneSentence) {
  const fs::path config = DefaultConfigDir();
  const auto sentence = [](const auto& load) {
    try {
      load();
    } catch (const UnknownPresetError& error) {
      return std::string(error.what());
    }
    ADD_FAILURE() << "no UnknownPresetError";
    return std::string();
  };
  const std::string arrays = (config / "arrays").string();
  const std::string maps = (config / "channel-maps").string();
  const std::string array_sentence = sentence([] { LoadArray("no-such-array"); });
  EXPECT_EQ(array_sentence.rfind(
                "\"no-such-array\" is neither a file nor a preset in " + arrays + " (presets: ", 0),
            0u)
      << array_sentence;
  EXPECT_NE(array_sentence.find("denton-3222"), std::string::npos) << array_sentence;
  const std::string map_sentence = sentence([] { LoadChannelMap("no-such-map"); });
  EXPECT_EQ(
      map_sentence.rfind("\"no-such-map\" is neither a file nor a preset in " + maps + " (presets: ", 0), 0u)
      << map_sentence;
  EXPECT_NE(map_sentence.find("default"), std::string::npos) << map_sentence;
}

}  // namespace
}  // namespace napkin::formats
