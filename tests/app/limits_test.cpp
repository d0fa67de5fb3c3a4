// The limits files (config/limits/*.json, app/limits.h, docs/formats.md
// "Limits"): each file's values and its cited source, the docs citing the
// same, and the refusals of a bad --limits (usage) or a malformed file (input).
#include "app/limits.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "common/error.h"
#include "tests/support/run_command.h"
#include "tests/support/test_support.h"

namespace napkin::app {
namespace {

namespace fs = std::filesystem;

void WriteLimitsText(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}
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
      // A scale's "max" is its lower performance limit; bands' the best band's upper value.
      {"euro-ncap-aop-v9.3-frontal-head-hiii50m",
       "Euro NCAP v9.3 frontal head (HIII 50M)",
       {{"hic15", 700.0}, {"a3ms_g", 80.0}},
       {"Euro NCAP Assessment Protocol - Adult Occupant Protection, version 9.3 (December 2023)", "500",
        "700", "72 g", "80 g", "4 points to 0", "lowest-scoring criterion"}},
      {"euro-ncap-aop-v9.3-mpdb-head-thor50m",
       "Euro NCAP v9.3 MPDB head (THOR-50M)",
       {{"hic15", 700.0}, {"a3ms_g", 80.0}},
       {"Euro NCAP Assessment Protocol - Adult Occupant Protection, version 9.3 (December 2023), MPDB",
        "pyisomme"}},
      {"iihs-small-overlap-head",
       "IIHS small overlap head",
       {{"hic15", 560.0}},
       {"Small Overlap Frontal Crashworthiness Evaluation: Guidelines for Rating Injury Measures", "560",
        "700", "840"}},
      {"iihs-moderate-overlap-2.0-head",
       "IIHS moderate overlap 2.0 head",
       {{"hic15", 560.0}},
       {"Moderate Overlap Frontal Crashworthiness Evaluation 2.0: Guidelines for Rating Injury Measures",
        "560", "700", "840"}},
      {"iihs-side-head-sid-iis",
       "IIHS side head (SID-IIs)",
       {{"hic15", 623.0}},
       {"Side Impact Crashworthiness Evaluation: Guidelines for Rating Injury Measures", "623", "779",
        "935"}},
  };
  EXPECT_EQ(LimitPresets(kConfig),
            (std::vector<std::string>{"euro-ncap-aop-v9.3-frontal-head-hiii50m",
                                      "euro-ncap-aop-v9.3-mpdb-head-thor50m", "euro-ncap-frontal-head",
                                      "fmvss201u", "fmvss208", "iihs-moderate-overlap-2.0-head",
                                      "iihs-side-head-sid-iis", "iihs-small-overlap-head"}));
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
    for (const Limit& limit : set.limits) EXPECT_FALSE(limit.requirement.empty()) << e.preset;
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
    EXPECT_NE(std::string(e.what()).find("\"fmvss999\" is neither a file nor a preset"), std::string::npos);
  }
  test_support::TempDir dir;
  const auto expect_input_error = [&](const std::string& text, const std::string& fragment) {
    const fs::path file = dir / "bad.json";
    WriteLimitsText(file, text);
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
    WriteLimitsText(file, text);
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
  EXPECT_EQ(error_of(head + R"("colour":"red","limits":[{"metric":"hic15","max":700,"requirement":"r"}]})"),
            "limits file " + file +
                ": the file has the unknown key \"colour\" (it may give name, title, applies_to, source, "
                "url, version, "
                "note, limits, combined, hard_contact).");
  EXPECT_EQ(
      error_of(head + R"("limits":[{"metric":"hic15","maximum":700,"max":700,"requirement":"r"}]})"),
      "limits file " + file +
          ": a limit has the unknown key \"maximum\" (it may give metric, max, scale, bands, requirement).");
  // The presets and a plausible file still load.
  EXPECT_EQ(error_of(head + R"("limits":[{"metric":"hic15","max":700,"requirement":"r"}]})"), "no error");
}

// Euro NCAP's sliding scale (AOP v9.3, the numbers of v8.0.3 3.1.1): 4 points at or below the
// higher performance limit, 0 at or above the lower, linear between.
TEST(LimitScales, EuroNcapPointsAtAndBetweenTheLimits) {
  const LimitSet set = LoadLimits("euro-ncap-aop-v9.3-frontal-head-hiii50m", kConfig);
  ASSERT_EQ(set.limits.size(), 2u);
  const Limit& hic15 = set.limits[0];
  const Limit& a3ms = set.limits[1];
  ASSERT_EQ(hic15.kind, LimitKind::kScale);
  EXPECT_EQ(hic15.higher_limit, 500.0);
  EXPECT_EQ(hic15.max, 700.0);
  EXPECT_EQ(hic15.points, 4.0);
  EXPECT_EQ(ScalePoints(hic15, 500.0), 4.0);
  EXPECT_EQ(ScalePoints(hic15, 600.0), 2.0);
  EXPECT_EQ(ScalePoints(hic15, 700.0), 0.0);
  EXPECT_EQ(ScalePoints(hic15, 350.0), 4.0);
  EXPECT_EQ(ScalePoints(hic15, 910.0), 0.0);
  EXPECT_DOUBLE_EQ(ScalePoints(hic15, 594.0), 4.0 * 106.0 / 200.0);  // the issue's 594: 2.12 points
  EXPECT_EQ(a3ms.metric, "a3ms_g");
  EXPECT_EQ(ScalePoints(a3ms, 76.0), 2.0);
  EXPECT_EQ(ScalePoints(a3ms, 72.0), 4.0);
  EXPECT_EQ(ScalePoints(a3ms, 74.0), 3.0);
  EXPECT_EQ(ScalePoints(a3ms, 80.0), 0.0);
}

// The head's points: the lowest of its criteria's; without a hard contact (the peak resultant at
// or below 80 g) 4 points; without the peak the rule is not applied.
TEST(LimitScales, TheHeadScoresItsLowestCriterionAndTheHardContactRule) {
  const LimitSet set = LoadLimits("euro-ncap-aop-v9.3-frontal-head-hiii50m", kConfig);
  ASSERT_TRUE(set.combined);
  ASSERT_TRUE(set.hard_contact);
  EXPECT_EQ(set.combined->name, "head");
  EXPECT_EQ(CombinedMaxPoints(set), 4.0);
  const auto rate = [&](double hic15, double a3ms, double peak) {
    return RateTest(set, [&](const std::string& metric) {
      if (metric == "hic15") return hic15;
      if (metric == "a3ms_g") return a3ms;
      if (metric == "peak_acc_g") return peak;
      return std::numeric_limits<double>::quiet_NaN();
    });
  };
  const double none = std::numeric_limits<double>::quiet_NaN();
  const TestRating hard = rate(600.0, 74.0, 90.0);
  EXPECT_EQ(hard.criteria[0].points, 2.0);
  EXPECT_EQ(hard.criteria[1].points, 3.0);
  EXPECT_EQ(hard.combined_points, 2.0);
  EXPECT_EQ(hard.hard_contact, HardContact::kAssumed);
  EXPECT_EQ(HardContactText(set, hard), "assumed (peak_acc_g 90 > 80)");
  EXPECT_EQ(rate(540.0, 77.0, 95.0).combined_points, 1.5);  // 3.2 and 1.5: the 3 ms acceleration's
  const TestRating soft = rate(600.0, 74.0, 78.0);
  EXPECT_EQ(soft.combined_points, 4.0);
  EXPECT_EQ(soft.hard_contact, HardContact::kNotAssumed);
  EXPECT_EQ(HardContactText(set, soft), "not assumed (peak_acc_g 78 ≤ 80): 4 points");
  EXPECT_EQ(rate(600.0, 74.0, 80.0).hard_contact, HardContact::kNotAssumed);  // "exceeds": 80 is not above
  const TestRating unknown = rate(600.0, 74.0, none);
  EXPECT_EQ(unknown.hard_contact, HardContact::kNotApplied);
  EXPECT_EQ(unknown.combined_points, 2.0);
  EXPECT_EQ(HardContactText(set, unknown), "not applied (no peak_acc_g)");
  EXPECT_TRUE(std::isnan(rate(none, 74.0, 90.0).combined_points));  // a criterion missing: no head points
  EXPECT_EQ(rate(none, 74.0, 70.0).combined_points, 4.0);           // ... unless no hard contact
}

// IIHS's bands: each up to and including its upper value, Poor above the last.
TEST(LimitBands, IihsBandEdges) {
  const auto band = [&](const char* preset, double value) {
    const LimitSet set = LoadLimits(preset, kConfig);
    return BandOf(set.limits.front(), value).name;
  };
  for (const char* frontal : {"iihs-small-overlap-head", "iihs-moderate-overlap-2.0-head"}) {
    EXPECT_EQ(band(frontal, 1.0), "Good") << frontal;
    EXPECT_EQ(band(frontal, 560.0), "Good") << frontal;
    EXPECT_EQ(band(frontal, 560.001), "Acceptable") << frontal;
    EXPECT_EQ(band(frontal, 700.0), "Acceptable") << frontal;
    EXPECT_EQ(band(frontal, 700.001), "Marginal") << frontal;
    EXPECT_EQ(band(frontal, 840.0), "Marginal") << frontal;
    EXPECT_EQ(band(frontal, 840.001), "Poor") << frontal;
    EXPECT_EQ(band(frontal, 5000.0), "Poor") << frontal;
  }
  EXPECT_EQ(band("iihs-side-head-sid-iis", 623.0), "Good");
  EXPECT_EQ(band("iihs-side-head-sid-iis", 623.001), "Acceptable");
  EXPECT_EQ(band("iihs-side-head-sid-iis", 779.0), "Acceptable");
  EXPECT_EQ(band("iihs-side-head-sid-iis", 779.001), "Marginal");
  EXPECT_EQ(band("iihs-side-head-sid-iis", 935.0), "Marginal");
  EXPECT_EQ(band("iihs-side-head-sid-iis", 935.001), "Poor");
}

// `query limits`' rows: the outcome by kind, and the combined head's row.
TEST(LimitsTable, PointsBandsAndTheCombinedHeadPerTest) {
  db::Table criteria;
  criteria.columns = {"test_id", "series", "variant", "hic15", "a3ms_g", "peak_acc_g"};
  criteria.rows = {{std::string("t1"), std::string("s"), std::string("v"), 600.0, 76.0, 93.5},
                   {std::string("t2"), std::string("s"), std::monostate{}, 450.0, db::Cell(), 60.0}};
  const db::Table euro =
      LimitsTable(criteria, LoadLimits("euro-ncap-aop-v9.3-frontal-head-hiii50m", kConfig));
  const std::vector<std::string> columns = {"test_id",      "series", "variant",    "limits", "metric",
                                            "value",        "limit",  "margin_pct", "meets",  "kind",
                                            "higher_limit", "points", "max_points", "band",   "hard_contact"};
  EXPECT_EQ(euro.columns, columns);
  ASSERT_EQ(euro.rows.size(), 6u);  // hic15, a3ms_g, head per test
  const auto cell = [&](const db::Table& table, std::size_t row, const std::string& column) {
    return table.rows[row][static_cast<std::size_t>(
        std::find(table.columns.begin(), table.columns.end(), column) - table.columns.begin())];
  };
  EXPECT_EQ(cell(euro, 0, "metric"), db::Cell(std::string("hic15")));
  EXPECT_EQ(cell(euro, 0, "kind"), db::Cell(std::string("scale")));
  EXPECT_EQ(cell(euro, 0, "limit"), db::Cell(700.0));
  EXPECT_EQ(cell(euro, 0, "higher_limit"), db::Cell(500.0));
  EXPECT_EQ(cell(euro, 0, "points"), db::Cell(2.0));
  EXPECT_EQ(cell(euro, 0, "max_points"), db::Cell(4.0));
  EXPECT_EQ(cell(euro, 0, "meets"), db::Cell());      // a scale gives points, not pass or fail
  EXPECT_EQ(cell(euro, 1, "points"), db::Cell(2.0));  // 76 g
  EXPECT_EQ(cell(euro, 2, "metric"), db::Cell(std::string("head")));
  EXPECT_EQ(cell(euro, 2, "kind"), db::Cell(std::string("combined")));
  EXPECT_EQ(cell(euro, 2, "points"), db::Cell(2.0));
  EXPECT_EQ(cell(euro, 2, "hard_contact"), db::Cell(std::string("assumed (peak_acc_g 93.5 > 80)")));
  EXPECT_EQ(cell(euro, 4, "value"), db::Cell());  // t2 has no a3ms_g
  EXPECT_EQ(cell(euro, 4, "points"), db::Cell());
  EXPECT_EQ(cell(euro, 5, "points"), db::Cell(4.0));  // no hard contact
  EXPECT_EQ(cell(euro, 5, "hard_contact"),
            db::Cell(std::string("not assumed (peak_acc_g 60 ≤ 80): 4 points")));

  const db::Table iihs = LimitsTable(criteria, LoadLimits("iihs-small-overlap-head", kConfig));
  ASSERT_EQ(iihs.rows.size(), 2u);
  EXPECT_EQ(cell(iihs, 0, "band"), db::Cell(std::string("Acceptable")));
  EXPECT_EQ(cell(iihs, 0, "kind"), db::Cell(std::string("bands")));
  EXPECT_EQ(cell(iihs, 0, "limit"), db::Cell(560.0));
  EXPECT_EQ(cell(iihs, 1, "band"), db::Cell(std::string("Good")));
  EXPECT_EQ(cell(iihs, 1, "points"), db::Cell());

  const db::Table fmvss = LimitsTable(criteria, LoadLimits("fmvss208", kConfig));
  EXPECT_EQ(cell(fmvss, 0, "meets"), db::Cell(std::string("yes")));
  EXPECT_EQ(cell(fmvss, 0, "kind"), db::Cell(std::string("maximum")));
  EXPECT_EQ(cell(fmvss, 0, "band"), db::Cell());
}

// A scale, bands or rule that is not what the file format says is refused naming the file and what.
TEST(LimitsFiles, MalformedScalesBandsAndRulesAreRefusedNamingThem) {
  test_support::TempDir dir;
  const std::string file = (dir / "bad.json").string();
  const auto error_of = [&](const std::string& limits, const std::string& more = "") -> std::string {
    WriteLimitsText(dir / "bad.json", R"({"name":"x","title":"t","applies_to":"a","source":"s","url":"u",)" +
                                          more + R"("limits":[)" + limits + "]}");
    try {
      LoadLimits(file, kConfig);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  const std::string scale =
      R"({"metric":"hic15","scale":{"higher_performance_limit":500,"lower_performance_limit":700,"points":4},"requirement":"r"})";
  EXPECT_EQ(error_of(scale), "no error");
  EXPECT_EQ(
      error_of(
          R"({"metric":"hic15","scale":{"higher_performance_limit":700,"lower_performance_limit":500,"points":4},"requirement":"r"})"),
      "limits file " + file +
          ": the higher performance limit of metric 'hic15', 700, must be below its lower performance limit, "
          "500 (full points at or below the higher, none at or above the lower).");
  EXPECT_EQ(
      error_of(
          R"({"metric":"hic15","scale":{"higher_performance_limit":500,"lower_performance_limit":700},"requirement":"r"})"),
      "limits file " + file + ": the points of metric 'hic15' must be a positive number.");
  EXPECT_EQ(error_of(R"({"metric":"hic15","max":700,"bands":[],"requirement":"r"})"),
            "limits file " + file +
                ": the limit of metric 'hic15' gives more than one of \"max\", \"scale\" and \"bands\".");
  EXPECT_EQ(
      error_of(
          R"({"metric":"hic15","bands":[{"band":"Good","max":700},{"band":"Poor","max":560}],"requirement":"r"})"),
      "limits file " + file +
          ": the last band of metric 'hic15', Poor, takes every value above the others: it has no \"max\".");
  EXPECT_EQ(
      error_of(
          R"({"metric":"hic15","bands":[{"band":"Good","max":700},{"band":"OK","max":560},{"band":"Poor"}],"requirement":"r"})"),
      "limits file " + file +
          ": the bands of metric 'hic15' must rise: band OK's max 560 is not above Good's 700.");
  EXPECT_EQ(error_of(R"({"metric":"hic15","bands":[{"band":"Good"}],"requirement":"r"})"),
            "limits file " + file +
                ": the \"bands\" of metric 'hic15' must be an array of at least 2 bands, best first.");
  EXPECT_EQ(error_of(scale + "," + scale),
            "limits file " + file + ": metric 'hic15' has two limits (a set gives each criterion one).");
  const std::string max = R"({"metric":"hic15","max":700,"requirement":"r"})";
  EXPECT_EQ(error_of(max, R"("combined":{"name":"head","rule":"lowest","requirement":"r"},)"),
            "limits file " + file + ": \"combined\" needs a limit with a \"scale\".");
  EXPECT_EQ(error_of(scale, R"("combined":{"name":"head","rule":"mean","requirement":"r"},)"),
            "limits file " + file +
                ": the \"rule\" of \"combined\" must be \"lowest\" (the lowest points of the criteria).");
  EXPECT_EQ(
      error_of(scale,
               R"("hard_contact":{"metric":"peak_acc_g","above":80,"points_without":4,"requirement":"r"},)"),
      "limits file " + file + ": \"hard_contact\" gives the points of a \"combined\" region: it needs one.");
  EXPECT_EQ(
      error_of(
          scale,
          R"("combined":{"name":"head","rule":"lowest","requirement":"r"},"hard_contact":{"metric":"peak_acc_g","above":80,"points_without":5,"requirement":"r"},)"),
      "limits file " + file +
          ": the \"points_without\" of \"hard_contact\", 5, exceeds the region's full points, 4.");
  EXPECT_EQ(
      error_of(
          scale,
          R"("combined":{"name":"head","rule":"lowest","requirement":"r"},"hard_contact":{"metric":"peak_acc_g","above":80,"points_without":4,"requirement":"r"},)"),
      "no error");
}

}  // namespace
}  // namespace napkin::app
