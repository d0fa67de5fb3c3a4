// Provenance with the binary (README "Batch runs", docs/formats.md "Version string"):
// `napkin --version`, `status` counting results by napkin version, and `run --outdated`
// recomputing the results of another version only.
#include <fmt/core.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cctype>
#include <map>

#include "common/version.h"
#include "engine/summary_fields.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"

namespace napkin {
namespace {

using test_support::Lines;
using test_support::RunNapkin;
using test_support::RunResult;
using ::testing::ElementsAre;
using ::testing::IsEmpty;
using ::testing::Optional;

constexpr const char* kOldVersion = "0.0.9+g0123456";

// The revision part of a version string: "g" and at least 7 hex digits, with an optional
// "-dirty", or "unknown" (docs/formats.md "Version string").
bool IsRevision(const std::string& revision) {
  if (revision == "unknown") return true;
  std::string commit = revision;
  if (commit.size() > 6 && commit.compare(commit.size() - 6, 6, "-dirty") == 0)
    commit.resize(commit.size() - 6);
  if (commit.size() < 8 || commit[0] != 'g') return false;
  for (std::size_t i = 1; i < commit.size(); ++i)
    if (!std::isxdigit(static_cast<unsigned char>(commit[i])) || std::isupper(commit[i])) return false;
  return true;
}

TEST(VersionCliTest, VersionNamesTheProjectVersionAndTheGitRevision) {
  napkin::test_support::TempDir dir;
  const RunResult run = RunNapkin(dir.path(), {"--version"});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.out, "napkin " + napkin::Version() + "\n");
  EXPECT_EQ(napkin::Version(), napkin::ProjectVersion() + "+" + napkin::GitRevision());
  EXPECT_EQ(napkin::ProjectVersion(), "0.1.0") << "CMakeLists.txt project(VERSION)";
  EXPECT_TRUE(IsRevision(napkin::GitRevision())) << napkin::GitRevision();
  EXPECT_FALSE(IsRevision("g12345")) << "too short";
  EXPECT_FALSE(IsRevision("G1a2b3c4"));
  EXPECT_TRUE(IsRevision("g1a2b3c4-dirty"));
}

class OutdatedCliTest : public ::testing::Test {
 protected:
  RunResult Napkin(std::vector<std::string> args) {
    args.insert(args.begin(), {"--db", db_});
    return RunNapkin(dir_.path(), args);
  }
  // The status table's rows "napkin version  config  results  failed" as
  // version -> (results, failed).
  std::map<std::string, std::pair<int, int>> VersionRows() {
    const RunResult status = Napkin({"status"});
    EXPECT_EQ(status.exit_code, 0) << status.err;
    std::map<std::string, std::pair<int, int>> rows;
    const std::vector<std::string> lines = Lines(status.out);
    std::size_t header = 0;
    while (header < lines.size() && lines[header].rfind("napkin version ", 0) != 0) ++header;
    EXPECT_LT(header, lines.size()) << status.out;
    const std::string config_column = "  default (";
    for (std::size_t i = header + 1; i < lines.size() && !lines[i].empty(); ++i) {
      const std::string& line = lines[i];
      const std::size_t config = line.find(config_column);
      if (config == std::string::npos) {
        ADD_FAILURE() << "no config column in '" << line << "'";
        continue;
      }
      std::string version = line.substr(0, config);
      version.erase(version.find_last_not_of(' ') + 1);
      std::istringstream counts(line.substr(line.find(')', config) + 1));
      int results = -1, failed = -1;
      counts >> results >> failed;
      rows[version] = {results, failed};
    }
    return rows;
  }

  napkin::test_support::TempDir dir_;
  std::string db_ = dir_ / "outdated.db";
};

TEST_F(OutdatedCliTest, StatusCountsByVersionAndRunOutdatedRecomputesTheOlderOnes) {
  ASSERT_EQ(Napkin({"synth", "--scenario", "random", "--count", "5", "--samples", "600"}).exit_code, 0);
  const RunResult first = Napkin({"run", "--threads", "2"});
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const std::string this_binary = napkin::Version() + " (this binary)";
  EXPECT_THAT(VersionRows(), ElementsAre(std::pair(this_binary, std::pair(5, 0))));

  // Two results of an older napkin, one from before version tracking.
  const std::map<std::string, std::optional<std::string>> older = {
      {"random-0002", kOldVersion}, {"random-0004", kOldVersion}, {"random-0005", std::nullopt}};
  std::map<std::string, engine::TestSummary> summaries;
  std::map<std::string, engine::Kinematics> kinematics;
  std::vector<std::int64_t> attempts;
  db::ConfigId config{};
  {
    db::Catalogue catalogue = db::Catalogue::Open(db_);
    db::CatalogueInspector inspector(catalogue);
    for (const db::TestRow& test : catalogue.ReadAllTests()) {
      config = *catalogue.ReadLatestResultConfig(test.id);
      summaries[test.external_id] = *catalogue.ReadSummary(test.id, config);
      kinematics[test.external_id] = *catalogue.ReadKinematics(test.id, config);
      if (older.count(test.external_id))
        inspector.SetResultVersion(test.id, config, older.at(test.external_id));
    }
    attempts = inspector.ReadJobAttempts(config);
  }
  const std::string unknown = "unknown (before version tracking)";
  EXPECT_THAT(VersionRows(),
              ElementsAre(std::pair(std::string(kOldVersion), std::pair(2, 0)),
                          std::pair(this_binary, std::pair(2, 0)), std::pair(unknown, std::pair(1, 0))));
  // The existing lines are as they were.
  const RunResult status = Napkin({"status"});
  EXPECT_THAT(Lines(status.out), ::testing::Contains(fmt::format("{:<8} {:>8}", "done", 5)));

  // A plain run touches nothing.
  const RunResult plain = Napkin({"run", "--threads", "2"});
  EXPECT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_THAT(plain.err, ::testing::HasSubstr("0 tests done, 0 failed, 5 up to date"));
  {
    db::Catalogue catalogue = db::Catalogue::Open(db_);
    EXPECT_EQ(db::CatalogueInspector(catalogue).ReadJobAttempts(config), attempts);
  }

  const RunResult outdated = Napkin({"run", "--outdated", "--threads", "2"});
  EXPECT_EQ(outdated.exit_code, 0) << outdated.err;
  EXPECT_THAT(outdated.err, ::testing::HasSubstr("3 tests done, 0 failed, 2 up to date"));
  EXPECT_THAT(VersionRows(), ElementsAre(std::pair(this_binary, std::pair(5, 0))));

  db::Catalogue catalogue = db::Catalogue::Open(db_);
  db::CatalogueInspector inspector(catalogue);
  const std::vector<std::int64_t> after = inspector.ReadJobAttempts(config);
  const std::vector<db::TestRow> tests = catalogue.ReadAllTests();
  ASSERT_EQ(after.size(), tests.size());
  for (std::size_t i = 0; i < tests.size(); ++i) {
    const std::string& id = tests[i].external_id;
    EXPECT_EQ(after[i], attempts[i] + (older.count(id) ? 1 : 0)) << id;
    EXPECT_THAT(inspector.ReadResultVersion(tests[i].id, config), Optional(napkin::Version())) << id;
    EXPECT_THAT(engine::DifferingSummaryFields(*catalogue.ReadSummary(tests[i].id, config), summaries[id]),
                IsEmpty())
        << id;
    const engine::Kinematics stored = *catalogue.ReadKinematics(tests[i].id, config);
    EXPECT_EQ(stored.omega_body, kinematics[id].omega_body) << id;  // bit for bit
    EXPECT_EQ(stored.pos_fixed, kinematics[id].pos_fixed) << id;
    EXPECT_EQ(stored.quat_fixed_from_body, kinematics[id].quat_fixed_from_body) << id;
  }
}

}  // namespace
}  // namespace napkin
