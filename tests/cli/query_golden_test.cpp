// `napkin query` filters end to end (docs/formats.md "Query filters"): the
// binary on a fixed catalogue, stdout compared with the golden files in
// tests/cli/golden/query/, exit status checked, stderr empty on success;
// every usage error exits 2 with one line.
//
// The catalogue is written through db::Catalogue with chosen numbers (no
// computation), so the output is the same at every optimisation level. Run
// with NAPKIN_UPDATE_GOLDEN=1 to rewrite the golden files after a deliberate
// change to the output, and review their diff.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "engine/injury_risk.h"
#include "engine/summary_fields.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"

namespace napkin::cli {

using namespace napkin::test_support;
namespace {

const fs::path kGoldenDir = fs::path(NAPKIN_SOURCE_DIR) / "tests" / "cli" / "golden" / "query";
const std::string kHostileSeries = "x'); DROP TABLE tests;--";
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

// The chosen numbers of one result. Fields not named here hold
// k + position/8 (k: the test's number), exact in binary.
struct ChosenResult {
  double hic15, hic36, hic_d, peak_acc_g, bric, max_rotation_deg;
};

engine::TestSummary ChosenSummary(int k, const ChosenResult& chosen) {
  engine::TestSummary summary;
  double position = 0.0;
  for (const engine::SummaryField& field : engine::SummaryFields()) field.Set(summary, k + position++ / 8.0);
  summary.hic15 = {chosen.hic15, 0.0125, 0.0275};
  summary.hic36.value = chosen.hic36;
  summary.hic_d = chosen.hic_d;  // 0.75446 hic36 + 166.4, written out in decimal
  summary.peak_acc_g = chosen.peak_acc_g;
  summary.bric = chosen.bric;
  summary.max_rotation_deg = chosen.max_rotation_deg;
  engine::FillInjuryRisks(summary);  // the risks their criteria stand for, as the engine stores them
  return summary;
}

// g01..g08: sled production, foam-a, foam-b; one pillar test; a test whose
// series is SQL-like text and whose HIC15 is NULL; g08 without a result.
// Config "default" (hash ab12...) has results for g01..g07; config "cfc180"
// (hash ab34...), written later, for g01, g03 and g05: their latest results.
void WriteFixedCatalogue(const fs::path& path) {
  db::CatalogueOptions options;
  options.clock = [] { return 1767225600.0; };  // 2026-01-01T00:00:00Z
  db::Catalogue catalogue = db::Catalogue::Open(path.string(), options);
  const db::ArrayId array = catalogue.WriteArray(
      {{}, "denton-3222", R"({"name":"denton-3222","length_unit":"in","sensors":[]})", "array-hash-denton"});
  const db::ConfigId defaults =
      catalogue.WriteConfig({{},
                             "default",
                             R"({"filter":"cfc1000"})",
                             "ab12c0ffee00000000000000000000000000000000000000000000000000aaaa",
                             {}});
  const db::ConfigId cfc180 =
      catalogue.WriteConfig({{},
                             "cfc180",
                             R"({"filter":"cfc180"})",
                             "ab34beef0000000000000000000000000000000000000000000000000000bbbb",
                             {}});

  struct Chosen {
    std::string id, series, variant;
    std::optional<ChosenResult> result;
    std::vector<engine::Finding> findings;
  };
  const std::vector<Chosen> tests = {
      {"g01",
       "sled",
       "production",
       ChosenResult{812.5, 845.25, 804.107315, 98.5, 0.75, 21.5},
       {{"bias", "cg_x", engine::Severity::kInfo, "Offset of 0.2 g removed."}}},
      {"g02", "sled", "production", ChosenResult{1034, 1101.5, 997.43769, 112.25, 0.875, 25.75}, {}},
      {"g03", "sled", "foam-a", ChosenResult{540.75, 566, 593.42436, 71.5, 0.5, 17.25}, {}},
      {"g04",
       "sled",
       "foam-a",
       ChosenResult{612, 640.5, 649.63163, 78, 0.625, 30.5},
       {{"saturation", "cg_y", engine::Severity::kWarning, "Channel cg_y is flat at 200 g for 0.4 ms."}}},
      {"g05", "sled", "foam-b", ChosenResult{455.5, 480.25, 528.729415, 64.75, 0.4375, 12}, {}},
      {"g06",
       "pillar",
       "production",
       ChosenResult{791, 802, 771.47692, 95, 0.9375, 34.25},
       {{"residual", std::nullopt, engine::Severity::kWarning, "Residual exceeds 2 m/s^2 for 1.5 ms."},
        {"bias", "cg_z", engine::Severity::kInfo, "Offset of 0.1 g removed."}}},
      {"g07", kHostileSeries, "foam-b", ChosenResult{kNan, 390.5, 461.01663, 52.5, 0.3125, 9.5}, {}},
      {"g08", "sled", "foam-b", std::nullopt, {}},
  };
  int k = 0;
  std::vector<db::TestId> keys;
  for (const Chosen& chosen : tests) {
    ++k;
    db::TestRow test;
    test.external_id = chosen.id;
    test.series = chosen.series;
    test.variant = chosen.variant;
    test.array_id = array;
    test.source_path = "/data/" + chosen.id + ".csv";
    test.content_hash = "content-" + chosen.id;
    keys.push_back(catalogue.WriteTest(test));
    if (!chosen.result) continue;
    engine::TestSummary summary = ChosenSummary(k, *chosen.result);
    summary.findings = chosen.findings;
    catalogue.WriteResult(keys.back(), defaults, summary, "exact");
  }
  // Under cfc180: lower peaks (the same tests, filtered harder).
  const std::vector<std::pair<int, ChosenResult>> cfc180_results = {
      {1, {760.5, 790, 762.4234, 92.25, 0.75, 21.5}},
      {3, {486.5, 510, 551.1746, 66, 0.5, 17.25}},
      {5, {410, 432.75, 492.892565, 60.5, 0.4375, 12}}};
  for (const auto& [number, chosen] : cfc180_results) {
    engine::TestSummary summary = ChosenSummary(number + 100, chosen);
    summary.findings = {{"bias", "cg_x", engine::Severity::kInfo, "Offset of 0.05 g removed."}};
    catalogue.WriteResult(keys[number - 1], cfc180, summary, "exact");
  }
}

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

class CliQueryGolden : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    WriteFixedCatalogue(*dir_ / "napkin.db");
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }

  static RunResult Query(std::vector<std::string> args) {
    args.insert(args.begin(), "query");
    return RunNapkin(dir_->path(), args);
  }

  // `napkin query args...` succeeds, says nothing on stderr, and prints the
  // golden file `name`.
  static void ExpectGolden(const std::string& name, const std::vector<std::string>& args) {
    const RunResult run = Query(args);
    EXPECT_EQ(run.exit_code, 0) << run.err;
    EXPECT_EQ(run.err, "");
    const fs::path golden = kGoldenDir / (name + ".txt");
    if (const char* update = std::getenv("NAPKIN_UPDATE_GOLDEN");
        update != nullptr && std::string(update) == "1") {
      std::ofstream(golden, std::ios::binary) << run.out;
      return;
    }
    ASSERT_TRUE(fs::exists(golden)) << golden << " is missing (NAPKIN_UPDATE_GOLDEN=1 writes it)";
    EXPECT_EQ(run.out, ReadFile(golden)) << "golden file " << golden;
  }

  // `napkin query args...` is a usage error: exit 2, one line holding `fragments`.
  static void ExpectUsageError(const std::vector<std::string>& args,
                               std::initializer_list<std::string> fragments) {
    const RunResult run = Query(args);
    EXPECT_EQ(run.exit_code, 2) << run.err;
    EXPECT_EQ(run.out, "");
    ExpectOneSentenceError(run, fragments);
  }

  static TempDir* dir_;
};
TempDir* CliQueryGolden::dir_ = nullptr;

TEST_F(CliQueryGolden, UnfilteredTablesInEveryFormat) {
  ExpectGolden("hic_table", {"hic"});
  ExpectGolden("hic_csv", {"hic", "--format", "csv"});
  ExpectGolden("rotation_json", {"rotation", "--format", "json"});
  ExpectGolden("tests_table", {"tests"});
}

TEST_F(CliQueryGolden, WhereFiltersInEveryFormat) {
  ExpectGolden("hic_where_and_table", {"hic", "--where", "hic15>500 and variant=foam-a"});
  ExpectGolden(
      "hic_where_or_csv",
      {"hic", "--where", "variant = foam-b or (series = pillar and hic36 >= 800)", "--format", "csv"});
  ExpectGolden("criteria_where_twice_json", {"criteria", "--where", "series=sled", "--where",
                                             "bric < 0.6 OR max_rotation_deg > 30", "--format", "json"});
  ExpectGolden("hic_where_hic_d_table", {"hic", "--where", "hic_d > 600", "--sort", "hic_d:desc"});
  ExpectGolden("quality_where_json", {"quality", "--where", "severity = warning", "--format", "json"});
  ExpectGolden("tests_where_csv",
               {"tests", "--where", "test_id >= g05 and array = denton-3222", "--format", "csv"});
  // NULL matches nothing: g07's HIC15 is NULL, so it is in neither answer.
  ExpectGolden("hic_where_null_csv", {"hic", "--where", "hic15 < 600 or hic15 >= 600", "--format", "csv"});
}

TEST_F(CliQueryGolden, RiskInEveryFormatWithWhereAndSort) {
  ExpectGolden("risk_table", {"risk"});
  ExpectGolden("risk_csv", {"risk", "--format", "csv"});
  ExpectGolden("risk_where_sort_json", {"risk", "--where", "hic15_p_ais3 > 0.1 or bric_p_ais4 < 0.1",
                                        "--sort", "bric_p_ais3:desc", "--format", "json"});
  ExpectGolden("risk_config_table", {"risk", "--config", "cfc180", "--sort", "hic15_p_ais3"});
}

TEST_F(CliQueryGolden, RiskIsTheCurveOfTheStoredCriterion) {
  // Each row of `query risk` is the engine's curve at the criterion `query
  // criteria` shows for the same test (NULL criterion: NULL risk).
  const RunResult risk = Query({"risk", "--format", "json"});
  const RunResult criteria = Query({"criteria", "--format", "json"});
  ASSERT_EQ(risk.exit_code, 0) << risk.err;
  ASSERT_EQ(criteria.exit_code, 0) << criteria.err;
  const nlohmann::json risks = nlohmann::json::parse(risk.out);
  const nlohmann::json tests = nlohmann::json::parse(criteria.out);
  ASSERT_EQ(risks.size(), 7u);
  ASSERT_EQ(risks.size(), tests.size());
  for (std::size_t i = 0; i < risks.size(); ++i) {
    ASSERT_EQ(risks[i]["test_id"], tests[i]["test_id"]);
    for (const engine::SummaryField* field : engine::RiskFields()) {
      const engine::RiskCurve& curve = *field->curve;
      const nlohmann::json& criterion = tests[i][curve.criterion];
      const nlohmann::json& value = risks[i][field->name];
      if (criterion.is_null()) {
        EXPECT_TRUE(value.is_null()) << risks[i];
        continue;
      }
      EXPECT_EQ(value.get<double>(), curve.risk(criterion.get<double>()))
          << risks[i]["test_id"] << field->name;
    }
  }
}

TEST_F(CliQueryGolden, SortAndLimit) {
  ExpectGolden("rotation_sort_desc_limit_json",
               {"rotation", "--sort", "max_rotation_deg:desc", "--limit", "3", "--format", "json"});
  ExpectGolden("hic_sort_two_keys_table", {"hic", "--sort", "variant", "--sort", "hic15:desc"});
  ExpectGolden("hic_sort_nulls_last_csv", {"hic", "--sort", "hic15", "--format", "csv"});
  ExpectGolden("hic_limit_zero_table", {"hic", "--limit", "0"});
  ExpectGolden("quality_sort_limit_csv",
               {"quality", "--sort", "check:desc", "--limit", "2", "--format", "csv"});
}

TEST_F(CliQueryGolden, ConfigSelectsTheResultSet) {
  ExpectGolden("hic_config_default_table", {"hic", "--config", "default"});
  ExpectGolden("criteria_config_prefix_csv", {"criteria", "--config", "AB34", "--format", "csv"});
  ExpectGolden("tests_config_json", {"tests", "--config", "cfc180", "--format", "json"});
  ExpectGolden("quality_config_table", {"quality", "--config", "ab12"});
  ExpectGolden("hic_config_where_sort_json", {"hic", "--config", "default", "--where", "hic15 > 600",
                                              "--sort", "hic15:desc", "--format", "json"});
}

TEST_F(CliQueryGolden, RepeatedSeriesAndVariants) {
  ExpectGolden("tests_series_variant_table", {"tests", "--series", "sled", "--series", "pillar", "--variant",
                                              "production", "--variant", "foam-b"});
  // One value per option: the positional query kind may follow.
  ExpectGolden("tests_series_before_kind_table", {"--series", "pillar", "tests"});
}

TEST_F(CliQueryGolden, SqlLikeTextIsAValue) {
  const std::string before = DumpCatalogue(dir_->path() / "napkin.db");
  ExpectGolden("hic_where_sql_like_csv",
               {"hic", "--where", "series=\"x'); DROP TABLE tests;--\" or hic36 > 1100", "--format", "csv"});
  ExpectGolden("tests_series_sql_like_csv", {"tests", "--series", kHostileSeries, "--format", "csv"});
  EXPECT_EQ(DumpCatalogue(dir_->path() / "napkin.db"), before) << "the catalogue is unchanged";
}

// `query limits` (issue 30 point 6): query criteria's rows, filtered and
// sorted as it does, each against each limit of a config/limits preset.
TEST_F(CliQueryGolden, LimitsListEachTestAgainstEachLimit) {
  ExpectGolden("limits_fmvss201u_table", {"limits", "--limits", "fmvss201u"});
  ExpectGolden("limits_euro_ncap_where_sort_json",
               {"limits", "--limits", "euro-ncap-frontal-head", "--where", "series = sled", "--sort",
                "hic15:desc", "--format", "json"});
  ExpectGolden("limits_fmvss208_csv", {"limits", "--limits", "fmvss208", "--format", "csv"});
  // Issue 44: Euro NCAP's sliding scales with the head's combined row and the hard-contact rule,
  // and IIHS's bands.
  ExpectGolden("limits_euro_ncap_v9_3_json", {"limits", "--limits", "euro-ncap-aop-v9.3-frontal-head-hiii50m",
                                              "--where", "series = sled", "--format", "json"});
  ExpectGolden("limits_iihs_small_overlap_csv",
               {"limits", "--limits", "iihs-small-overlap-head", "--format", "csv"});
  ExpectUsageError({"limits"}, {"`napkin query limits` needs --limits NAME", "fmvss201u"});
  ExpectUsageError({"hic", "--limits", "fmvss208"}, {"--limits applies to `napkin query limits` only"});
  ExpectUsageError({"limits", "--limits", "fmvss999"}, {"\"fmvss999\" is neither a file nor a preset",
                                                        "euro-ncap-frontal-head, fmvss201u, fmvss208"});
}

TEST_F(CliQueryGolden, UsageErrorsAreOneLineExitTwo) {
  ExpectUsageError(
      {"hic", "--where", "hic16>700"},
      {"unknown field 'hic16' at column 1", "the fields are test_id, series, variant, hic15,", "hic_d"});
  ExpectUsageError({"hic", "--where", "bric>1"}, {"unknown field 'bric'"});
  ExpectUsageError(
      {"risk", "--where", "hic15>1"},
      {"unknown field 'hic15'",
       "the fields are test_id, series, variant, hic15_p_ais3, hic36_p_ais4, bric_p_ais3, bric_p_ais4"});
  ExpectUsageError({"rotation", "--where", "bric>1 and"},
                   {"expected a field name at column 11, found the end"});
  ExpectUsageError({"hic", "--where", "hic15>>700"}, {"expected a value after '>' at column 7, found '>'"});
  ExpectUsageError({"hic", "--where", "(hic15>700"}, {"the '(' at column 1 is never closed"});
  ExpectUsageError({"hic", "--where", "hic15>abc"}, {"field 'hic15' holds numbers, but 'abc'"});
  ExpectUsageError({"hic", "--where", "variant='foam-a'"}, {"single quote at column 9"});
  ExpectUsageError(
      {"quality", "--where", "check=bias", "--where", "hic15>1"},
      {"unknown field 'hic15'", "the fields are test_id, series, variant, check, channel, severity, detail"});
  ExpectUsageError({"hic", "--sort", "hic16"}, {"--sort \"hic16\": unknown field 'hic16'"});
  ExpectUsageError({"hic", "--sort", "hic15:down"}, {"the direction after ':' is asc or desc, not 'down'"});
  ExpectUsageError({"hic", "--limit", "-1"}, {"--limit takes a whole number of rows, 0 or more, not '-1'"});
  ExpectUsageError({"hic", "--limit", "ten"}, {"not 'ten'"});
  ExpectUsageError({"hic", "--config", "cfc60"},
                   {"--config 'cfc60' is neither the name nor a hash prefix of a config",
                    "default (hash ab12c0ffee00), cfc180 (hash ab34beef0000)"});
  ExpectUsageError({"hic", "--config", "ab"}, {"--config 'ab' starts the hashes of 2 configs",
                                               "default (hash ab12c0ffee00), cfc180 (hash "
                                               "ab34beef0000)",
                                               "give more of the hash"});
}

TEST(CliQueryConfig, NoConfigsYetAndAmbiguousNames) {
  TempDir dir;
  ASSERT_EQ(RunNapkin(dir.path(), {"init"}).exit_code, 0);
  const RunResult none = RunNapkin(dir.path(), {"query", "hic", "--config", "default"});
  EXPECT_EQ(none.exit_code, 2);
  ExpectOneSentenceError(none, {"no processing configs yet", "run `napkin run` first"});
  {
    db::Catalogue catalogue = db::Catalogue::Open((dir / "napkin.db").string());
    catalogue.WriteConfig({{}, "default", R"({"a":1})", "1111aaaa", {}});
    catalogue.WriteConfig({{}, "default", R"({"a":2})", "2222bbbb", {}});
  }
  const RunResult twice = RunNapkin(dir.path(), {"query", "hic", "--config", "default"});
  EXPECT_EQ(twice.exit_code, 2);
  ExpectOneSentenceError(twice, {"--config 'default' names 2 configs: default (hash 1111aaaa), default (hash "
                                 "2222bbbb); give a hash prefix instead"});
  const RunResult by_hash = RunNapkin(dir.path(), {"query", "hic", "--config", "2222", "--format", "csv"});
  EXPECT_EQ(by_hash.exit_code, 0) << by_hash.err;
  EXPECT_EQ(by_hash.err, "");
  EXPECT_EQ(Lines(by_hash.out).size(), 1u) << "the header only: no results under that config";
}

}  // namespace
}  // namespace napkin::cli
