// `napkin compare` on a fixed catalogue whose results are written with chosen
// numbers (db::Catalogue::WriteResult): golden table and JSON output, the
// numbers recomputed independently from the stored per-test results (read
// back with `napkin query --format json` and db::Catalogue::ReadSummary), the
// CSV contract, and the usage errors (docs/formats.md "napkin compare").
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <boost/math/distributions/non_central_t.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "app/comparison.h"
#include "db/job_queue.h"
#include "engine/injury_risk.h"
#include "engine/summary_fields.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"

namespace napkin::app {

using namespace napkin::test_support;
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct FixedTest {
  const char* id;
  const char* variant;
  double hic15;       // NaN: absent (NULL) in the catalogue
  double peak_acc_g;  //
  double offset;      // no-gravity config: every value + offset (NaN: no result under it)
};

// Series "sled": five production tests, five foam-a tests with one more whose
// HIC15 is absent, and one foam-b test (n < 2). Series "drop": one test, never run.
const std::vector<FixedTest> kTests = {
    {"s01", "production", 912.5, 98.5, 1.5},  {"s02", "production", 1004.25, 104.0, 2.0},
    {"s03", "production", 871.0, 95.25, 0.5}, {"s04", "production", 955.75, 101.75, 3.25},
    {"s05", "production", 990.5, 99.0, 1.0},  {"s06", "foam-a", 701.25, 80.0, -0.5},
    {"s07", "foam-a", 745.0, 84.5, 0.75},     {"s08", "foam-a", 688.5, 79.25, 2.5},
    {"s09", "foam-a", 730.75, 83.0, 1.25},    {"s10", "foam-a", 712.0, 81.5, 0.25},
    {"s11", "foam-a", kNaN, 82.25, kNaN},     {"s12", "foam-b", 640.0, 75.0, kNaN},
};

// The other default metrics: a smooth function of the test's position.
double OtherMetric(std::size_t metric, std::size_t test) {
  return (10.0 + 3.0 * static_cast<double>(metric)) * (1.0 + 0.037 * static_cast<double>(test * test % 7));
}

class CliCompare : public ::testing::Test {
 protected:
  void SetUp() override {
    db::Catalogue catalogue = db::Catalogue::Open((dir_ / "napkin.db").string());
    const db::ArrayId array = catalogue.WriteArray(
        {{}, "ideal-3222", R"({"name":"ideal-3222","length_unit":"in","sensors":[]})", "array-hash-ideal"});
    const db::ConfigId no_gravity =
        catalogue.WriteConfig({{}, "no-gravity", R"({"gravity":false})", "e1b2c3d4e5f60718293a", {}});
    const db::ConfigId standard =
        catalogue.WriteConfig({{}, "default", R"({"gravity":true})", "d0a1b2c3d4e5f6071829", {}});
    std::vector<db::TestId> keys;
    for (const FixedTest& fixed : kTests) {
      db::TestRow test;
      test.external_id = fixed.id;
      test.series = "sled";
      test.variant = fixed.variant;
      test.array_id = array;
      test.source_path = std::string("/data/") + fixed.id + ".csv";
      test.content_hash = std::string("content-") + fixed.id;
      keys.push_back(catalogue.WriteTest(test));
    }
    db::TestRow never_run;
    never_run.external_id = "d01";
    never_run.series = "drop";
    never_run.array_id = array;
    never_run.source_path = "/data/d01.csv";
    never_run.content_hash = "content-d01";
    catalogue.WriteTest(never_run);
    // no-gravity first, default last: default is each test's latest result.
    for (const bool standard_pass : {false, true}) {
      for (std::size_t i = 0; i < kTests.size(); ++i) {
        const double offset = standard_pass ? 0.0 : kTests[i].offset;
        if (std::isnan(offset)) continue;
        catalogue.WriteResult(keys[i], standard_pass ? standard : no_gravity, Summary(i, offset), "exact");
      }
    }
  }

  static engine::TestSummary Summary(std::size_t test, double offset) {
    engine::TestSummary summary;
    std::size_t metric = 0;
    for (const engine::SummaryField& field : engine::SummaryFields())
      field.Set(summary, OtherMetric(metric++, test) + offset);
    summary.hic15.value = kTests[test].hic15 + offset;
    summary.peak_acc_g = kTests[test].peak_acc_g + offset;
    // BrIC in the range of the curves' slope; the risks as the engine stores them.
    summary.bric = 0.45 + 0.05 * static_cast<double>(test % 5) + offset / 20.0;
    engine::FillInjuryRisks(summary);
    return summary;
  }

  RunResult Compare(std::vector<std::string> args) {
    args.insert(args.begin(), "compare");
    return RunNapkin(dir_.path(), args);
  }

  nlohmann::json CompareJson(std::vector<std::string> args) {
    args.insert(args.end(), {"--format", "json"});
    const RunResult run = Compare(args);
    EXPECT_EQ(run.exit_code, 0) << run.err;
    EXPECT_EQ(run.err, "");
    return nlohmann::json::parse(run.out);
  }

  napkin::test_support::TempDir dir_;
};

// ---------------------------------------------------------------- golden output

TEST_F(CliCompare, TableByVariantIsTheGoldenText) {
  const RunResult run = Compare(
      {"--series", "sled", "--by", "variant", "--baseline", "production", "--metrics", "hic15,peak_acc_g"});
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_EQ(run.err, "");
  EXPECT_EQ(run.out, R"(series sled: variants compared with variant 'production'
change in % of the baseline, [95 % confidence interval] (Welch's t), two-sided p: of the geometric mean on the log scale, of the mean on the linear
n80: tests per variant that would detect the observed difference with 80 % power (two-sided t, alpha 0.05)
detects: the smallest fall/rise these tests detect with 80 % power; equiv: equivalence within ±10 % shown by two one-sided tests (p < 0.05)

hic15 (log scale: ratio of geometric means)
  variant     n   mean       sd  median    min      max  n80   detects      equiv  vs production
  production  5  946.8  55.2549  955.75    871  1004.25    -         -          -  (baseline)
  foam-a      5  715.5  22.6226     712  688.5      745    3  -9/+10 %  no p>0.99  -24.4 % [-29.7, -18.6]  p<0.0001
  foam-b      1    640        -     640    640      640    -         -          -  n < 2: no difference (1)

peak_acc_g (log scale: ratio of geometric means)
  variant     n   mean       sd  median    min   max  n80  detects      equiv  vs production
  production  5   99.7   3.3326      99  95.25   104    -        -          -  (baseline)
  foam-a      6  81.75  1.93649  81.875  79.25  84.5    2  -5/+6 %  no p>0.99  -18.0 % [-21.4, -14.5]  p<0.0001
  foam-b      1     75        -      75     75    75    -        -          -  n < 2: no difference (1)

(1) n < 2: with fewer than 2 tests in the group or the baseline there is no difference, interval or p-value (null in --format json and csv).
)");
}

TEST_F(CliCompare, JsonByVariantIsTheGoldenText) {
  const RunResult run = Compare({"--series", "sled", "--metrics", "hic15", "--format", "json"});
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_EQ(run.err, "");
  EXPECT_EQ(run.out, R"([
  {
    "metric": "hic15",
    "group": "foam-a",
    "n": 5,
    "mean": 715.5,
    "sd": 22.622582743798286,
    "median": 712.0,
    "min": 688.5,
    "max": 745.0,
    "baseline": "foam-a",
    "scale": "log",
    "diff": null,
    "diff_pct": null,
    "ci_low": null,
    "ci_high": null,
    "ratio": null,
    "ratio_ci_low": null,
    "ratio_ci_high": null,
    "p_value": null,
    "n_for_80pct_power": null,
    "mdd_low_pct": null,
    "mdd_high_pct": null,
    "equivalence_pct": null,
    "tost_p_value": null
  },
  {
    "metric": "hic15",
    "group": "foam-b",
    "n": 1,
    "mean": 640.0,
    "sd": null,
    "median": 640.0,
    "min": 640.0,
    "max": 640.0,
    "baseline": "foam-a",
    "scale": "log",
    "diff": null,
    "diff_pct": null,
    "ci_low": null,
    "ci_high": null,
    "ratio": null,
    "ratio_ci_low": null,
    "ratio_ci_high": null,
    "p_value": null,
    "n_for_80pct_power": null,
    "mdd_low_pct": null,
    "mdd_high_pct": null,
    "equivalence_pct": 10.0,
    "tost_p_value": null
  },
  {
    "metric": "hic15",
    "group": "production",
    "n": 5,
    "mean": 946.8,
    "sd": 55.254920595364176,
    "median": 955.75,
    "min": 871.0,
    "max": 1004.25,
    "baseline": "foam-a",
    "scale": "log",
    "diff": 231.29999999999995,
    "diff_pct": 32.1971063938523,
    "ci_low": null,
    "ci_high": null,
    "ratio": 1.321971063938523,
    "ratio_ci_low": 1.229087588423804,
    "ratio_ci_high": 1.4218738439397165,
    "p_value": 7.654560300180584e-05,
    "n_for_80pct_power": 3,
    "mdd_low_pct": -9.130557409300808,
    "mdd_high_pct": 10.04799539755882,
    "equivalence_pct": 10.0,
    "tost_p_value": 0.999604876210941
  }
]
)");
}

TEST_F(CliCompare, TableByConfigIsTheGoldenText) {
  const RunResult run =
      Compare({"--series", "sled", "--by", "config", "--baseline", "default", "--metrics", "hic15"});
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_EQ(run.err, "");
  EXPECT_EQ(run.out, R"(series sled: processing configs compared with config 'default'
mean per-test change in % of the baseline over the same tests, [95 % confidence interval] (paired t), two-sided p: of the ratio on the log scale, of the difference on the linear
n80: tests that would detect the observed mean difference with 80 % power (two-sided paired t, alpha 0.05)
detects: the smallest fall/rise these tests detect with 80 % power; equiv: equivalence within ±10 % shown by two one-sided tests (p < 0.05)

hic15 (log scale: ratio of geometric means)
  config       n     mean       sd   median  min      max  n80        detects         equiv  vs default
  default     11  813.773   134.62      745  640  1004.25    -              -             -  (baseline)
  no-gravity  10    832.4  128.712  808.625  691  1006.25    9  -0.13/+0.13 %  yes p<0.0001  +0.1 % [+0.1, +0.2]  p=0.0071 (10 pairs)
)");
}

// ------------------------------------------------- independent recomputation

// Relative agreement to 1e-9 (absolute near 0); null must match NaN.
void ExpectClose(const nlohmann::json& value, double expected, const std::string& what) {
  if (std::isnan(expected)) {
    EXPECT_TRUE(value.is_null()) << what << " = " << value;
    return;
  }
  ASSERT_TRUE(value.is_number()) << what << " = " << value;
  const double actual = value.get<double>();
  EXPECT_LE(std::abs(actual - expected), 1e-9 * std::max(1.0, std::abs(expected)))
      << what << ": " << actual << " vs " << expected;
}

struct Independent {
  double n, mean, sd, median, min, max;
};

// The statistics by their textbook definitions, written out here.
Independent Straightforward(std::vector<double> x) {
  std::sort(x.begin(), x.end());
  const double n = static_cast<double>(x.size());
  double sum = 0.0;
  for (const double v : x) sum += v;
  const double mean = sum / n;
  double squares = 0.0;
  for (const double v : x) squares += (v - mean) * (v - mean);
  const double median = x.size() % 2 ? x[x.size() / 2] : 0.5 * (x[x.size() / 2 - 1] + x[x.size() / 2]);
  return {n, mean, x.size() > 1 ? std::sqrt(squares / (n - 1.0)) : kNaN, median, x.front(), x.back()};
}

// diff, diff_pct, ci_low, ci_high, p from diff, se, df (t quantile and cdf from Boost).
std::array<double, 5> Interval(double diff, double baseline_mean, double se, double df) {
  const boost::math::students_t t_distribution(df);
  const double q = boost::math::quantile(t_distribution, 0.975);
  const double p = 2.0 * (1.0 - boost::math::cdf(t_distribution, std::abs(diff / se)));
  return {diff, 100.0 * diff / baseline_mean, diff - q * se, diff + q * se, p};
}

void ExpectRow(const nlohmann::json& row, const Independent& stats, const std::array<double, 5>& difference) {
  const std::string what = row["metric"].get<std::string>() + "/" + row["group"].get<std::string>();
  EXPECT_EQ(row["n"].get<double>(), stats.n) << what;
  ExpectClose(row["mean"], stats.mean, what + " mean");
  ExpectClose(row["sd"], stats.sd, what + " sd");
  ExpectClose(row["median"], stats.median, what + " median");
  ExpectClose(row["min"], stats.min, what + " min");
  ExpectClose(row["max"], stats.max, what + " max");
  const char* keys[] = {"diff", "diff_pct", "ci_low", "ci_high", "p_value"};
  for (int k = 0; k < 5; ++k) ExpectClose(row[keys[k]], difference[k], what + " " + keys[k]);
}

TEST_F(CliCompare, ByVariantNumbersEqualAnIndependentRecomputationFromTheStoredResults) {
  // The per-test results as `napkin query` reads them back (each test's latest result).
  const RunResult query = RunNapkin(dir_.path(), {"query", "hic", "--series", "sled", "--format", "json"});
  ASSERT_EQ(query.exit_code, 0) << query.err;
  const nlohmann::json stored = nlohmann::json::parse(query.out);
  ASSERT_EQ(stored.size(), kTests.size());

  // The difference of means (the log scale is checked against scipy:
  // python/tests/test_compare_statistics.py).
  const nlohmann::json rows =
      CompareJson({"--series", "sled", "--metrics", "hic15,peak_acc_g,a3ms_g", "--scale", "linear"});
  ASSERT_EQ(rows.size(), 9u);
  std::size_t checked = 0;
  for (const std::string metric : {"hic15", "peak_acc_g", "a3ms_g"}) {
    std::map<std::string, std::vector<double>> by_variant;
    for (const auto& test : stored)
      if (!test[metric].is_null()) by_variant[test["variant"]].push_back(test[metric].get<double>());
    const std::vector<double>& baseline = by_variant.at("foam-a");  // first in name order
    const Independent b = Straightforward(baseline);
    for (const auto& row : rows) {
      if (row["metric"] != metric) continue;
      EXPECT_EQ(row["baseline"], "foam-a");
      const std::vector<double>& values = by_variant.at(row["group"]);
      const Independent a = Straightforward(values);
      std::array<double, 5> difference = {kNaN, kNaN, kNaN, kNaN, kNaN};
      if (row["group"] != "foam-a" && a.n >= 2 && b.n >= 2) {
        const double va = a.sd * a.sd / a.n, vb = b.sd * b.sd / b.n;
        const double df = (va + vb) * (va + vb) / (va * va / (a.n - 1) + vb * vb / (b.n - 1));
        difference = Interval(a.mean - b.mean, b.mean, std::sqrt(va + vb), df);
      }
      ExpectRow(row, a, difference);
      ++checked;
    }
  }
  EXPECT_EQ(checked, 9u);
  // The foam-a HIC15 of s11 is absent: n counts the five present values.
  EXPECT_EQ(rows[0]["group"], "foam-a");
  EXPECT_EQ(rows[0]["n"], 5);
  EXPECT_EQ(rows[3]["n"], 6);  // peak_acc_g of foam-a
}

// The fewest whole repeats per variant at which the two-sided Welch t (equal
// n, Welch–Satterthwaite df) reaches 80 % power at alpha 0.05 for the observed
// difference and spreads, found by stepping n up one at a time (R's
// power.t.test form: the upper tail of the non-central t only).
double IndependentRepeatsFor80PercentPower(double diff, double sd_a, double sd_b) {
  if (diff == 0.0 || (sd_a == 0.0 && sd_b == 0.0)) return kNaN;
  for (double n = 2.0;; n += 1.0) {
    const double se = std::sqrt((sd_a * sd_a + sd_b * sd_b) / n);
    const double va = sd_a * sd_a / n, vb = sd_b * sd_b / n;
    const double df = (va + vb) * (va + vb) / ((va * va + vb * vb) / (n - 1.0));
    const double q = boost::math::quantile(boost::math::students_t(df), 0.975);
    const double power = 1.0 - boost::math::cdf(boost::math::non_central_t(df, std::abs(diff) / se), q);
    if (power >= 0.8) return n;
  }
}

TEST_F(CliCompare, RiskStatisticsEqualARecomputationFromQueryRisk) {
  const RunResult query = RunNapkin(dir_.path(), {"query", "risk", "--series", "sled", "--format", "json"});
  ASSERT_EQ(query.exit_code, 0) << query.err;
  const nlohmann::json stored = nlohmann::json::parse(query.out);
  ASSERT_EQ(stored.size(), kTests.size());
  const std::vector<std::string> metrics = {"hic15_p_ais3", "hic36_p_ais4", "bric_p_ais3", "bric_p_ais4"};
  const nlohmann::json rows = CompareJson({"--series", "sled", "--baseline", "production", "--metrics",
                                           "hic15_p_ais3,hic36_p_ais4,bric_p_ais3,bric_p_ais4"});
  ASSERT_EQ(rows.size(), 12u);
  std::size_t powers = 0;
  for (const std::string& metric : metrics) {
    std::map<std::string, std::vector<double>> by_variant;
    for (const auto& test : stored)
      if (!test[metric].is_null()) by_variant[test["variant"]].push_back(test[metric].get<double>());
    const Independent b = Straightforward(by_variant.at("production"));
    for (const auto& row : rows) {
      if (row["metric"] != metric) continue;
      const Independent a = Straightforward(by_variant.at(row["group"]));
      std::array<double, 5> difference = {kNaN, kNaN, kNaN, kNaN, kNaN};
      double repeats = kNaN;
      if (row["group"] != "production" && a.n >= 2 && b.n >= 2) {
        const double va = a.sd * a.sd / a.n, vb = b.sd * b.sd / b.n;
        const double df = (va + vb) * (va + vb) / (va * va / (a.n - 1) + vb * vb / (b.n - 1));
        difference = Interval(a.mean - b.mean, b.mean, std::sqrt(va + vb), df);
        repeats = IndependentRepeatsFor80PercentPower(a.mean - b.mean, a.sd, b.sd);
      }
      ExpectRow(row, a, difference);
      ASSERT_TRUE(row.contains("n_for_80pct_power")) << row;
      if (std::isnan(repeats)) {
        EXPECT_TRUE(row["n_for_80pct_power"].is_null()) << row;
      } else {
        ASSERT_TRUE(row["n_for_80pct_power"].is_number_integer()) << row;
        EXPECT_EQ(row["n_for_80pct_power"].get<double>(), repeats) << row;
        ++powers;
      }
    }
  }
  EXPECT_EQ(powers, 4u) << "foam-a against production, for each of the four risks";
}

TEST_F(CliCompare, ByConfigNumbersEqualAnIndependentPairedRecomputation) {
  // The stored summaries under each config, read one by one.
  db::Catalogue catalogue = OpenForReading(dir_ / "napkin.db");
  std::map<std::string, db::ConfigId> configs;
  for (const db::ConfigRow& config : catalogue.ReadAllConfigs()) configs[config.name] = config.id;
  const nlohmann::json rows = CompareJson({"--series", "sled", "--by", "config", "--baseline", "d0a1b2",
                                           "--metrics", "hic15,bric", "--scale", "linear"});
  ASSERT_EQ(rows.size(), 4u);
  for (const auto& row : rows) {
    EXPECT_EQ(row["baseline"], "default");
    const engine::SummaryField* field = nullptr;
    for (const engine::SummaryField& f : engine::SummaryFields())
      if (row["metric"] == f.name) field = &f;
    ASSERT_NE(field, nullptr);
    std::vector<double> values, differences, baseline_values;
    for (const FixedTest& fixed : kTests) {
      const db::TestId key = *catalogue.FindTestByExternalId(fixed.id);
      const auto own = catalogue.ReadSummary(key, configs.at(row["group"]));
      const auto base = catalogue.ReadSummary(key, configs.at("default"));
      if (own && !std::isnan(field->Get(*own))) values.push_back(field->Get(*own));
      if (own && base && !std::isnan(field->Get(*own)) && !std::isnan(field->Get(*base))) {
        differences.push_back(field->Get(*own) - field->Get(*base));
        baseline_values.push_back(field->Get(*base));
      }
    }
    std::array<double, 5> difference = {kNaN, kNaN, kNaN, kNaN, kNaN};
    if (row["group"] == "no-gravity") {
      ASSERT_EQ(differences.size(), 10u);
      const Independent d = Straightforward(differences);
      const Independent b = Straightforward(baseline_values);
      difference = Interval(d.mean, b.mean, d.sd / std::sqrt(d.n), d.n - 1.0);
    }
    ExpectRow(row, Straightforward(values), difference);
  }
}

// ------------------------------------------------------------ contract shape

TEST_F(CliCompare, DefaultMetricsJsonKeysAndCsvColumns) {
  const nlohmann::ordered_json rows =
      nlohmann::ordered_json::parse(Compare({"--series", "sled", "--format", "json"}).out);
  const std::vector<std::string> metrics = DefaultComparisonMetrics();
  ASSERT_EQ(rows.size(), 3 * metrics.size());
  const std::vector<std::string> keys = {"metric",
                                         "group",
                                         "n",
                                         "mean",
                                         "sd",
                                         "median",
                                         "min",
                                         "max",
                                         "baseline",
                                         "scale",
                                         "diff",
                                         "diff_pct",
                                         "ci_low",
                                         "ci_high",
                                         "ratio",
                                         "ratio_ci_low",
                                         "ratio_ci_high",
                                         "p_value",
                                         "n_for_80pct_power",
                                         "mdd_low_pct",
                                         "mdd_high_pct",
                                         "equivalence_pct",
                                         "tost_p_value"};
  for (std::size_t i = 0; i < rows.size(); ++i) {
    std::vector<std::string> row_keys;
    for (const auto& item : rows[i].items()) row_keys.push_back(item.key());
    EXPECT_EQ(row_keys, keys);
    EXPECT_EQ(rows[i]["metric"], metrics[i / 3]);
    EXPECT_EQ(rows[i]["group"], (std::array<const char*, 3>{"foam-a", "foam-b", "production"}[i % 3]));
  }
  // Baseline row and the n < 2 group: the difference fields are null.
  for (const char* key : {"diff", "diff_pct", "ratio", "ratio_ci_low", "ratio_ci_high", "p_value",
                          "n_for_80pct_power", "mdd_low_pct", "mdd_high_pct", "tost_p_value"}) {
    EXPECT_TRUE(rows[0][key].is_null()) << key;
    EXPECT_TRUE(rows[1][key].is_null()) << key;
    EXPECT_TRUE(rows[2][key].is_number()) << key;
  }
  // hic15 on the log scale: the interval is the ratio's.
  EXPECT_EQ(rows[2]["scale"], "log");
  EXPECT_TRUE(rows[2]["ci_low"].is_null());
  EXPECT_TRUE(rows[2]["ci_high"].is_null());
  EXPECT_EQ(rows[2]["equivalence_pct"], 10.0);
  EXPECT_TRUE(rows[1]["sd"].is_null());

  const RunResult csv = Compare({"--series", "sled", "--metrics", "hic15", "--format", "csv"});
  ASSERT_EQ(csv.exit_code, 0);
  EXPECT_EQ(csv.err, "");
  const std::vector<std::string> lines = Lines(csv.out);
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(
      lines[0],
      "metric,group,n,mean,sd,median,min,max,baseline,scale,diff,diff_pct,ci_low,ci_high,ratio,ratio_ci_low,"
      "ratio_ci_high,p_value,n_for_80pct_power,mdd_low_pct,mdd_high_pct,equivalence_pct,tost_p_value");
  EXPECT_EQ(lines[2], "hic15,foam-b,1,640,,640,640,640,foam-a,log,,,,,,,,,,,,10,");
  const nlohmann::json json = CompareJson({"--series", "sled", "--metrics", "hic15"});
  EXPECT_EQ(
      lines[3].rfind("hic15,production,5," + util::FormatNumber(json[2]["mean"].get<double>()) + ",", 0), 0u)
      << lines[3];
}

TEST_F(CliCompare, ConfigChoosesTheResultsComparedByVariant) {
  const nlohmann::json rows =
      CompareJson({"--series", "sled", "--metrics", "hic15", "--config", "no-gravity"});
  ASSERT_EQ(rows.size(), 2u);  // foam-b has no result under no-gravity
  EXPECT_EQ(rows[0]["group"], "foam-a");
  EXPECT_EQ(rows[1]["group"], "production");
  // production under no-gravity: the chosen numbers plus their offsets.
  EXPECT_DOUBLE_EQ(rows[1]["max"].get<double>(), 1004.25 + 2.0);
  EXPECT_DOUBLE_EQ(rows[1]["min"].get<double>(), 871.0 + 0.5);
}

// ------------------------------------------------------------------ errors

TEST_F(CliCompare, UsageErrorsExitTwoWithOneLineListingTheChoices) {
  const RunResult series = Compare({"--series", "nope"});
  EXPECT_EQ(series.exit_code, 2);
  EXPECT_EQ(series.out, "");
  ExpectOneSentenceError(series, {"unknown series 'nope'", "drop, sled"});

  const RunResult baseline = Compare({"--series", "sled", "--baseline", "foam-c"});
  EXPECT_EQ(baseline.exit_code, 2);
  ExpectOneSentenceError(baseline, {"unknown baseline 'foam-c'", "foam-a, foam-b, production"});

  const RunResult metric = Compare({"--series", "sled", "--metrics", "hic15,hic99"});
  EXPECT_EQ(metric.exit_code, 2);
  ExpectOneSentenceError(metric, {"unknown metric 'hic99'", "hic15, hic15_t1_s", "max_rotation_deg"});

  const RunResult config = Compare({"--series", "sled", "--config", "fast"});
  EXPECT_EQ(config.exit_code, 2);
  ExpectOneSentenceError(config, {"--config 'fast' is neither the name nor a hash prefix of a config",
                                  "no-gravity (hash e1b2c3d4e5f6)", "default (hash d0a1b2c3d4e5)"});

  const RunResult two = Compare({"--series", "sled", "--config", "default", "--config", "no-gravity"});
  EXPECT_EQ(two.exit_code, 2);
  ExpectOneSentenceError(two, {"--by config"});

  const RunResult by = Compare({"--series", "sled", "--by", "colour"});
  EXPECT_EQ(by.exit_code, 2);
  EXPECT_EQ(by.out, "");
}

// Issue 29 point 18: --baseline names a config by the rule of --config (one
// matcher): a hash prefix in any case, and a name two configs share is
// ambiguous, not unknown.
TEST_F(CliCompare, BaselineAndConfigMatchAConfigByOneRule) {
  for (const std::string prefix : {"D0A1B2", "d0a1b2"}) {
    const nlohmann::json rows =
        CompareJson({"--series", "sled", "--by", "config", "--baseline", prefix, "--metrics", "hic15"});
    ASSERT_EQ(rows.size(), 2u) << prefix;
    for (const auto& row : rows) EXPECT_EQ(row["baseline"], "default") << prefix;
    const nlohmann::json chosen = CompareJson({"--series", "sled", "--config", prefix, "--metrics", "hic15"});
    EXPECT_FALSE(chosen.empty()) << prefix;
  }
  {
    db::Catalogue catalogue = db::Catalogue::Open((dir_ / "napkin.db").string());
    const db::ConfigId other =
        catalogue.WriteConfig({{}, "default", R"({"gravity":true,"cfc":60})", "f00dfeed00112233aabb", {}});
    catalogue.WriteResult(*catalogue.FindTestByExternalId("s01"), other, Summary(0, 7.0), "exact");
  }
  const RunResult baseline = Compare({"--series", "sled", "--by", "config", "--baseline", "default"});
  EXPECT_EQ(baseline.exit_code, 2);
  ExpectOneSentenceError(baseline, {"--baseline 'default' names 2 configs", "default (hash d0a1b2c3d4e5)",
                                    "default (hash f00dfeed0011)", "give a hash prefix instead"});
  const RunResult config = Compare({"--series", "sled", "--config", "default"});
  EXPECT_EQ(config.exit_code, 2);
  ExpectOneSentenceError(config, {"--config 'default' names 2 configs", "default (hash d0a1b2c3d4e5)",
                                  "default (hash f00dfeed0011)", "give a hash prefix instead"});
  // A hash prefix tells them apart.
  const nlohmann::json rows =
      CompareJson({"--series", "sled", "--by", "config", "--baseline", "F00D", "--metrics", "hic15"});
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows.front()["baseline"], "default@f00dfeed");
}

TEST_F(CliCompare, BadScaleEquivalenceOrLimitsAreUsageErrorsNamingTheOption) {
  const RunResult scale = Compare({"--series", "sled", "--scale", "cubic"});
  EXPECT_EQ(scale.exit_code, 2);
  EXPECT_EQ(scale.out, "");
  ExpectOneSentenceError(scale, {"--scale", "log or linear", "cubic"});
  for (const std::string bad : {"0", "100", "-5", "ten", "nan"}) {
    const RunResult equivalence = Compare({"--series", "sled", "--equivalence", bad});
    EXPECT_EQ(equivalence.exit_code, 2) << bad;
    EXPECT_EQ(equivalence.out, "") << bad;
    ExpectOneSentenceError(equivalence, {"--equivalence must be a margin in percent", "it is '" + bad + "'"});
  }
  const RunResult limits = Compare({"--series", "sled", "--limits", "fmvss999"});
  EXPECT_EQ(limits.exit_code, 2);
  ExpectOneSentenceError(limits, {"\"fmvss999\" is neither a file nor a preset", "fmvss201u"});
  const RunResult empty = Compare({"--series", "sled", "--limits", ""});
  EXPECT_EQ(empty.exit_code, 2);
}

TEST_F(CliCompare, LimitsCountTheTestsWithinAndNameTheWorst) {
  // FMVSS 208: HIC15 <= 700. production 871..1004 (none within), foam-a 688.5..745 (1 of 5), foam-b 640.
  const nlohmann::json rows =
      CompareJson({"--series", "sled", "--metrics", "peak_acc_g", "--limits", "fmvss208"});
  ASSERT_EQ(rows.size(), 6u);  // peak_acc_g, then hic15 the limit compares
  for (const auto& row : rows) {
    if (row["metric"] == "peak_acc_g") {
      EXPECT_TRUE(row["limit"].is_null()) << row;
      continue;
    }
    EXPECT_EQ(row["limit"], 700.0);
    if (row["group"] == "foam-a") {
      EXPECT_EQ(row["tests_within_limit"], 1);
      EXPECT_EQ(row["worst_test"], "s07");
      EXPECT_NEAR(row["limit_margin_pct"].get<double>(), 100.0 * (700.0 - 745.0) / 700.0, 1e-12);
    } else if (row["group"] == "production") {
      EXPECT_EQ(row["tests_within_limit"], 0);
      EXPECT_EQ(row["worst_test"], "s02");
    } else {
      EXPECT_EQ(row["tests_within_limit"], 1);
      EXPECT_EQ(row["worst_test"], "s12");
    }
  }
  const RunResult table = Compare({"--series", "sled", "--metrics", "hic15", "--limits", "fmvss208"});
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("  FMVSS 208 limit 700: foam-a 1 of 5 within (worst s07 745, margin -6.4 %)"),
            std::string::npos)
      << table.out;
}

// A further test (issue 44): compare's JSON gains the set's name and, per variant, the chance a
// further test exceeds the limit (python/tests/test_further_test.py checks the numbers against
// scipy), the expected points of a sliding scale, nulls for a maximum and for foam-b's one test;
// two sets limiting one metric are refused.
TEST_F(CliCompare, LimitsGiveAFurtherTestsChanceAndExpectedPoints) {
  const nlohmann::json rows = CompareJson(
      {"--series", "sled", "--metrics", "hic15", "--limits", "euro-ncap-aop-v9.3-frontal-head-hiii50m"});
  std::size_t scales = 0;
  for (const auto& row : rows) {
    if (row["metric"] != "hic15" && row["metric"] != "a3ms_g") {
      EXPECT_TRUE(row["exceed_probability"].is_null()) << row;
      continue;
    }
    EXPECT_EQ(row["limits"], "Euro NCAP v9.3 frontal head (HIII 50M)") << row;
    EXPECT_EQ(row["limit"], row["metric"] == "hic15" ? 700.0 : 80.0) << row;
    if (row["group"] == "foam-b") {  // one test: not estimated
      for (const char* key : {"exceed_probability", "expected_points", "points_low", "points_high"})
        EXPECT_TRUE(row[key].is_null()) << key << " " << row;
      continue;
    }
    ++scales;
    const double p = row["exceed_probability"].get<double>();
    EXPECT_GE(p, 0.0) << row;
    EXPECT_LE(p, 1.0) << row;
    const double low = row["points_low"].get<double>(), high = row["points_high"].get<double>();
    EXPECT_LE(0.0, low) << row;
    EXPECT_LE(low, high) << row;
    EXPECT_LE(high, 4.0) << row;
    EXPECT_GE(row["expected_points"].get<double>(), 0.0) << row;
  }
  EXPECT_EQ(scales, 4u);  // hic15 and a3ms_g of production and foam-a
  // production's HIC15 (871 to 1004): a further test beyond 700 is all but certain, and scores about nothing.
  for (const auto& row : rows)
    if (row["metric"] == "hic15" && row["group"] == "production") {
      EXPECT_GT(row["exceed_probability"].get<double>(), 0.99) << row;
      EXPECT_LT(row["expected_points"].get<double>(), 0.05) << row;
    }
  const nlohmann::json maximum =
      CompareJson({"--series", "sled", "--metrics", "hic15", "--limits", "fmvss208"});
  for (const auto& row : maximum) {
    EXPECT_EQ(row["limits"], "FMVSS 208") << row;
    EXPECT_EQ(row["exceed_probability"].is_number(), row["group"] != "foam-b") << row;
    EXPECT_TRUE(row["expected_points"].is_null()) << row;
    EXPECT_TRUE(row["points_low"].is_null()) << row;
  }
  // The table prints each chance as a percentage the JSON's probability rounds to,
  // with the digits that tell 99.8 % from certainty (never "1e+02 %").
  const RunResult maximum_table = Compare({"--series", "sled", "--metrics", "hic15", "--limits", "fmvss208"});
  ASSERT_EQ(maximum_table.exit_code, 0) << maximum_table.err;
  for (const auto& row : maximum) {
    if (!row["exceed_probability"].is_number()) continue;
    const std::string group = row["group"].get<std::string>() + " ";
    const std::size_t at = maximum_table.out.find("P(further > 700) ", maximum_table.out.find("; " + group));
    const std::size_t from = at == std::string::npos ? maximum_table.out.find("P(further > 700) ") : at;
    ASSERT_NE(from, std::string::npos) << maximum_table.out;
    const std::string shown =
        maximum_table.out.substr(from + 17, maximum_table.out.find(' ', from + 17) - from - 17);
    EXPECT_EQ(shown.find('e'), std::string::npos) << shown;
  }
  const RunResult both = Compare(
      {"--series", "sled", "--limits", "fmvss208", "--limits", "euro-ncap-aop-v9.3-frontal-head-hiii50m"});
  EXPECT_EQ(both.exit_code, 2);
  ExpectOneSentenceError(both,
                         {"--limits: FMVSS 208 and Euro NCAP v9.3 frontal head (HIII 50M) both limit hic15"});
  const RunResult table =
      Compare({"--series", "sled", "--metrics", "hic15", "--limits", "iihs-small-overlap-head"});
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find(
                "  IIHS small overlap head bands Good ≤ 560, Acceptable ≤ 700, Marginal ≤ 840, Poor above: "),
            std::string::npos)
      << table.out;
  EXPECT_NE(table.out.find("P(further > 560) "), std::string::npos) << table.out;
}

TEST_F(CliCompare, SeriesWithoutResultsSaysRunFirst) {
  const RunResult run = Compare({"--series", "drop"});
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_EQ(run.out, "");
  ExpectOneSentenceError(run, {"series 'drop' has no results", "run `napkin run` first"});
}

// After a run whose only test failed, compare says so and points to `status`, not to `run` again
// (issue 42, point 17).
TEST_F(CliCompare, SeriesWhoseTestsFailedSaysSoAndPointsToStatus) {
  {
    db::Catalogue catalogue = db::Catalogue::Open((dir_ / "napkin.db").string());
    const db::ConfigId config = *catalogue.FindConfigByHash("d0a1b2c3d4e5f6071829");
    db::JobQueue queue(catalogue);
    db::JobScope scope;
    scope.tests.series = {"drop"};
    ASSERT_EQ(queue.EnqueueMissing(config, scope), 1);
    const std::vector<db::Job> jobs = queue.ClaimJobs(config, "test-worker", 1, 60.0, scope);
    ASSERT_EQ(jobs.size(), 1u);
    ASSERT_TRUE(queue.FailJob(jobs[0].id, "test-worker", "channel cg_z is clipped."));
  }
  const RunResult run = Compare({"--series", "drop"});
  EXPECT_EQ(run.exit_code, 1);
  ExpectOneSentenceError(run, {"series 'drop' has no results: its test failed processing",
                               "`napkin status` lists the failures"});
  EXPECT_EQ(run.err.find("run `napkin run` first"), std::string::npos) << run.err;
}

}  // namespace
}  // namespace napkin::app
