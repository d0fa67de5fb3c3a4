// The fuzz targets of `make fuzz` under the test build's sanitizers
// (docs/architecture.md "Fuzzing"). Every input that ever crashed, hung or
// tripped a sanitizer (fuzz/regressions/<target>/) runs through the same
// target and must be accepted or rejected with an InputError, never anything
// else; the seeds (fuzz/seeds/<target>/, napkin's own valid files) must be
// accepted, which shows the target really reaches the parser.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz/fuzz_inputs.h"

namespace napkin::fuzz {
namespace {

namespace fs = std::filesystem;

const fs::path kFuzzDir = fs::path(NAPKIN_SOURCE_DIR) / "fuzz";

std::string ReadBytes(const fs::path& path) {
  std::ifstream stream(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>());
}

// The files of `folder` (none when it does not exist), sorted by name.
std::vector<fs::path> FilesIn(const fs::path& folder) {
  std::vector<fs::path> files;
  if (fs::is_directory(folder))
    for (const auto& entry : fs::directory_iterator(folder))
      if (entry.is_regular_file() && entry.path().filename() != "README.md") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

TEST(FuzzRegressionTest, EveryRegressionInputIsAcceptedOrRejectedWithAnInputError) {
  int inputs = 0;
  for (const FuzzTarget& target : FuzzTargets()) {
    for (const fs::path& file : FilesIn(kFuzzDir / "regressions" / target.name)) {
      SCOPED_TRACE(file.string() + " through " + std::string(target.what));
      const std::string input = ReadBytes(file);
      EXPECT_NO_THROW(target.run(input));  // an InputError is caught by the target
      ++inputs;
    }
  }
  RecordProperty("regression_inputs", inputs);
}

// Every folder in `parent` is named after a fuzz target.
void ExpectEveryFolderNamesATarget(const fs::path& parent) {
  for (const auto& entry : fs::directory_iterator(parent)) {
    if (!entry.is_directory()) continue;
    const std::string name = entry.path().filename().string();
    EXPECT_TRUE(std::any_of(FuzzTargets().begin(), FuzzTargets().end(),
                            [&](const FuzzTarget& target) { return target.name == name; }))
        << entry.path() << " is not the folder of a fuzz target";
  }
}

TEST(FuzzRegressionTest, EveryRegressionFolderNamesATarget) {
  ExpectEveryFolderNamesATarget(kFuzzDir / "regressions");
}

TEST(FuzzSeedTest, EveryTargetHasSeedsAndAcceptsThem) {
  for (const FuzzTarget& target : FuzzTargets()) {
    const std::vector<fs::path> seeds = FilesIn(kFuzzDir / "seeds" / target.name);
    EXPECT_FALSE(seeds.empty()) << "no seeds for fuzz target " << target.name;
    for (const fs::path& seed : seeds) {
      SCOPED_TRACE(seed.string() + " through " + std::string(target.what));
      EXPECT_EQ(target.run(ReadBytes(seed)), Outcome::kAccepted);
    }
  }
}

// `make fuzz` and fuzz/CMakeLists.txt take the targets from the seed folders: each folder is a
// target of the table, as each target has a folder (EveryTargetHasSeedsAndAcceptsThem).
TEST(FuzzSeedTest, EverySeedFolderNamesATarget) { ExpectEveryFolderNamesATarget(kFuzzDir / "seeds"); }

TEST(FuzzSeedTest, TruncatedSeedsAreRejectedWithAnInputError) {
  // Cutting a valid file short loses declared samples (ISO-MME, UDS-1992) or
  // rows (CSV): each target reports it as bad input.
  for (const std::string_view name : {"csv", "isomme_channel", "uds1992", "dts_slice_csv"}) {
    const FuzzTarget& target = GetFuzzTarget(name);
    for (const fs::path& seed : FilesIn(kFuzzDir / "seeds" / target.name)) {
      SCOPED_TRACE(seed.string());
      const std::string input = ReadBytes(seed);
      EXPECT_EQ(target.run(input.substr(0, input.size() / 8)), Outcome::kRejected);
    }
  }
}

TEST(FuzzTargetTest, UnknownTargetIsRefused) { EXPECT_THROW(GetFuzzTarget("xml"), std::invalid_argument); }

}  // namespace
}  // namespace napkin::fuzz
