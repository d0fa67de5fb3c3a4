// Issue 19 items 14 and 15 end to end (`napkin compare`, docs/formats.md
// "napkin compare", docs/algorithms.md "Comparing groups of tests"):
//  14. three tests with bit-identical HIC15 473.5561725417905 gave sd 6.96e-14
//      and a mean below min = max, then p < 0.0001 against another group
//      without scatter: now sd 0, the mean is the value, and no interval.
//  15. a variant named "(none)" was pooled with the tests without a variant
//      (one group): import refuses the name, and a catalogue that already
//      holds it keeps the two groups apart.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "formats/csv.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"

namespace napkin {
namespace {

using test_support::CommandResult;
using test_support::ExpectOneSentenceError;

struct GroupTest {
  std::optional<std::string> variant;
  double hic15;
};

class CompareGroups : public ::testing::Test {
 protected:
  // Series "sled": one test per entry, its result HIC15 as given.
  void WriteSeries(const std::vector<GroupTest>& tests) {
    db::Catalogue catalogue = db::Catalogue::Open((dir_ / "napkin.db").string());
    const db::ArrayId array = catalogue.WriteArray(
        {{}, "ideal-3222", R"({"name":"ideal-3222","length_unit":"in","sensors":[]})", "array-hash-ideal"});
    const db::ConfigId config =
        catalogue.WriteConfig({{}, "default", R"({"gravity":true})", "d0a1b2c3d4e5f6071829", {}});
    for (std::size_t i = 0; i < tests.size(); ++i) {
      db::TestRow test;
      test.external_id = "t" + std::to_string(i);
      test.series = "sled";
      test.variant = tests[i].variant;
      test.array_id = array;
      test.source_path = "/data/t" + std::to_string(i) + ".csv";
      test.content_hash = "content-" + std::to_string(i);
      engine::TestSummary summary;
      summary.hic15.value = tests[i].hic15;
      catalogue.WriteResult(catalogue.WriteTest(test), config, summary, "exact");
    }
  }

  // `compare --series sled --metrics hic15 --format json`, parsed.
  nlohmann::json CompareJson(const std::vector<std::string>& extra = {}) {
    std::vector<std::string> args = {"compare", "--series", "sled", "--metrics", "hic15", "--format", "json"};
    args.insert(args.end(), extra.begin(), extra.end());
    const CommandResult run = test_support::RunNapkin(dir_.path(), args);
    EXPECT_EQ(run.exit_code, 0) << run.err;
    return run.exit_code == 0 ? nlohmann::json::parse(run.out) : nlohmann::json::array();
  }

  test_support::TempDir dir_;
};

TEST_F(CompareGroups, IdenticalValuesHaveThatMeanNoScatterAndNoInterval) {
  constexpr double kHic = 473.5561725417905;
  WriteSeries({{"a", kHic}, {"a", kHic}, {"a", kHic}, {"b", 473.0}, {"b", 473.0}, {"b", 473.0}});
  const nlohmann::json rows = CompareJson();
  ASSERT_EQ(rows.size(), 2u) << rows.dump();
  const nlohmann::json& a = rows[0];
  EXPECT_EQ(a.at("group"), "a");
  EXPECT_EQ(a.at("mean").get<double>(), kHic);
  EXPECT_EQ(a.at("sd").get<double>(), 0.0);
  EXPECT_EQ(a.at("min").get<double>(), kHic);
  EXPECT_EQ(a.at("max").get<double>(), kHic);
  const nlohmann::json& b = rows[1];
  EXPECT_EQ(b.at("group"), "b");
  EXPECT_EQ(b.at("diff").get<double>(), 473.0 - kHic);
  // No scatter in either group: a difference, but no interval and no p-value.
  EXPECT_TRUE(b.at("ci_low").is_null()) << b.dump();
  EXPECT_TRUE(b.at("ci_high").is_null()) << b.dump();
  EXPECT_TRUE(b.at("p_value").is_null()) << b.dump();

  const CommandResult table =
      test_support::RunNapkin(dir_.path(), {"compare", "--series", "sled", "--metrics", "hic15"});
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("(no scatter: no interval)"), std::string::npos) << table.out;
  EXPECT_EQ(table.out.find("p<0.0001"), std::string::npos) << table.out;
}

TEST_F(CompareGroups, ImportRefusesTheVariantNameNone) {
  formats::WriteSignalsCsv(test_support::SynthNapTest(1).signals, dir_ / "a.csv");
  const CommandResult refused = test_support::RunNapkin(
      dir_.path(), {"import", "--array", "denton-3222", "--series", "sled", "--variant", "(none)", "a.csv"});
  EXPECT_EQ(refused.exit_code, 2) << refused.out;
  ExpectOneSentenceError(refused, {"--variant '(none)'", "without a variant"});
  EXPECT_FALSE(std::filesystem::exists(dir_ / "napkin.db") &&
               test_support::DumpCatalogue(dir_ / "napkin.db").find("a.csv") != std::string::npos);
}

// A catalogue written before the name was refused: the tests of variant
// "(none)" and those without a variant are two groups, never pooled.
TEST_F(CompareGroups, AStoredVariantNamedNoneIsKeptApartFromTestsWithoutAVariant) {
  WriteSeries({{std::nullopt, 500.0}, {std::nullopt, 520.0}, {"(none)", 700.0}, {"(none)", 740.0}});
  // Name order: '"' sorts before '(', so the stored variant is the default baseline.
  const nlohmann::json rows = CompareJson();
  ASSERT_EQ(rows.size(), 2u) << rows.dump();
  EXPECT_EQ(rows[0].at("group"), "\"(none)\"");
  EXPECT_EQ(rows[0].at("n"), 2);
  EXPECT_EQ(rows[0].at("mean").get<double>(), 720.0);
  EXPECT_EQ(rows[1].at("group"), "(none)");
  EXPECT_EQ(rows[1].at("n"), 2);
  EXPECT_EQ(rows[1].at("mean").get<double>(), 510.0);
  EXPECT_EQ(rows[1].at("diff").get<double>(), -210.0);
  // Either can be the baseline, by the name compare shows.
  const nlohmann::json swapped = CompareJson({"--baseline", "(none)"});
  ASSERT_EQ(swapped.size(), 2u);
  EXPECT_EQ(swapped[0].at("group"), "(none)");
  EXPECT_EQ(swapped[1].at("group"), "\"(none)\"");
  EXPECT_EQ(swapped[1].at("diff").get<double>(), 210.0);
}

}  // namespace
}  // namespace napkin
