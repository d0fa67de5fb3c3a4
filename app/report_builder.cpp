// The report `napkin report` and `napkin demo` write: one self-contained HTML file (docs/formats.md "HTML
// report"): the comparison of each series' variants (app/comparison.h, as
// `napkin compare`), then each selected test's latest result: criteria, time
// histories, screening findings and final pose. Reads the catalogue one test
// at a time and streams the page (formats/html_report.h HtmlReportWriter):
// its memory does not grow with the number of tests.
#include "app/report_builder.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "app/comparison.h"
#include "app/correlation.h"
#include "app/report_limits.h"
#include "app/result_selection.h"
#include "app/verdict.h"
#include "app/where_parser.h"
#include "common/error.h"
#include "common/joined.h"
#include "common/version.h"
#include "engine/kinematics.h"
#include "engine/overlay.h"
#include "engine/statistics.h"
#include "engine/units.h"
#include "formats/html_report.h"
#include "util/atomic_file.h"
#include "util/output_destination.h"
#include "util/text.h"

namespace napkin::app {
namespace {

// "1 test", "6 tests".
std::string Tests(std::size_t count) { return std::to_string(count) + (count == 1 ? " test" : " tests"); }

// A cell of the compare table as text: 5 significant digits, "—" for null.
std::string CellText(const db::Cell& cell) {
  if (const auto* integer = std::get_if<std::int64_t>(&cell)) return std::to_string(*integer);
  if (const auto* text = std::get_if<std::string>(&cell)) return *text;
  if (const auto* number = std::get_if<double>(&cell); number && std::isfinite(*number))
    return util::FormatNumber(*number, 5);
  return "—";
}

// The verdict of a comparison as the page shows it (app/verdict.h), with
// the note its rules table words.
formats::ReportVerdict VerdictOf(const Comparison& comparison) {
  const SeriesVerdict verdict = BuildVerdict(comparison);
  return {verdict.baseline, verdict.columns, verdict.rows, verdict.sentences, {VerdictNote(comparison)}};
}

std::string Milliseconds(double seconds) { return util::FormatNumber(seconds * 1000.0, 4) + " ms"; }

// The overlaid curves of a series: each test's latest result, its resultant
// CG acceleration (g) and, for tests with rotation, its resultant angular
// velocity (rad/s), aligned as `options` say, resampled onto one common time
// base, with each group's mean ± 1 sd. Reads each test's kinematics twice
// (once for the time base, once for the values), so only the resampled
// traces are held.
void AddOverlays(db::Catalogue& catalogue, const Comparison& comparison, const ReportOptions& options,
                 formats::ReportComparison& report) {
  db::TestFilter filter;
  filter.series = {comparison.series};
  struct OverlayTest {
    std::string test_id;
    std::size_t group;
    db::TestId key;
    db::ConfigId config;
    double shift_s = 0.0;  // subtracted from its time axis
    bool rotation = false;
  };
  std::vector<OverlayTest> tests;
  for (const db::LabelledResult& result : catalogue.ReadResults(filter, db::ResultSelection::kLatest)) {
    const auto group =
        std::find(comparison.groups.begin(), comparison.groups.end(), VariantGroup(result.variant));
    if (group == comparison.groups.end()) continue;
    const std::optional<db::TestId> key = catalogue.FindTestByExternalId(result.test_id);
    if (!key) continue;
    tests.push_back({result.test_id, static_cast<std::size_t>(group - comparison.groups.begin()), *key,
                     result.config_id});
  }
  std::stable_sort(tests.begin(), tests.end(), [](const OverlayTest& a, const OverlayTest& b) {
    return std::tie(a.group, a.test_id) < std::tie(b.group, b.test_id);
  });
  if (tests.empty()) return;

  auto acceleration_g = [](const engine::Kinematics& k) -> Eigen::VectorXd {
    // As the per-test chart: fixed-frame resultant, body axes without rotation (the same length).
    return (engine::HasRotation(k) ? k.acc_fixed : k.acc_body).rowwise().norm() / engine::kStandardGravity;
  };
  // Pass 1: alignment and the time base.
  std::vector<engine::TimeSeries> spans;  // each test's aligned time axis (no values)
  std::vector<engine::TimeSeries> rotation_spans;
  std::vector<std::string> without_onset;
  for (OverlayTest& test : tests) {
    const engine::Kinematics k = ReadResultKinematics(catalogue, test.key, test.config);
    test.rotation = engine::HasRotation(k) && k.size() > 0 && k.omega_body.rows() == k.size();
    if (options.align == OverlayAlignment::kOnset) {
      const std::optional<double> onset =
          engine::OnsetTime(k.time_s, acceleration_g(k), options.onset_threshold_g);
      if (onset)
        test.shift_s = *onset;
      else
        without_onset.push_back(test.test_id);
    }
    engine::TimeSeries span{k.time_s.array() - test.shift_s, {}};
    if (test.rotation) rotation_spans.push_back(span);
    spans.push_back(std::move(span));
  }
  const Eigen::VectorXd base = engine::CommonTimeBase(spans, kOverlayBasePoints);
  const Eigen::VectorXd rotation_base = engine::CommonTimeBase(rotation_spans, kOverlayBasePoints);
  if (base.size() < 2) return;

  // Pass 2: every test on the base; the corridors last.
  const std::size_t rotation_tests = rotation_spans.size();
  const std::size_t group_count = comparison.groups.size();
  Eigen::MatrixXd acc(base.size(), static_cast<Eigen::Index>(tests.size() + 2 * group_count));
  Eigen::MatrixXd omega(rotation_base.size(), static_cast<Eigen::Index>(rotation_tests + 2 * group_count));
  std::vector<formats::ReportOverlay::Trace> acc_traces, omega_traces;
  std::vector<std::vector<Eigen::Index>> acc_columns(group_count), omega_columns(group_count);
  for (const OverlayTest& test : tests) {
    const engine::Kinematics k = ReadResultKinematics(catalogue, test.key, test.config);
    const Eigen::VectorXd time = k.time_s.array() - test.shift_s;
    const auto column = static_cast<Eigen::Index>(acc_traces.size());
    acc.col(column) = engine::ResampleOnto({time, acceleration_g(k)}, base);
    acc_columns[test.group].push_back(column);
    acc_traces.push_back({test.test_id, test.group, formats::ReportOverlay::Trace::Kind::kTest});
    if (!test.rotation || rotation_base.size() < 2) continue;
    const auto rotation_column = static_cast<Eigen::Index>(omega_traces.size());
    omega.col(rotation_column) = engine::ResampleOnto({time, k.omega_body.rowwise().norm()}, rotation_base);
    omega_columns[test.group].push_back(rotation_column);
    omega_traces.push_back({test.test_id, test.group, formats::ReportOverlay::Trace::Kind::kTest});
  }
  auto add_corridors = [&](Eigen::MatrixXd& values, std::vector<formats::ReportOverlay::Trace>& traces,
                           const std::vector<std::vector<Eigen::Index>>& columns) {
    for (std::size_t g = 0; g < group_count; ++g) {
      if (columns[g].empty()) continue;  // a variant without a trace here has no corridor
      Eigen::MatrixXd members(values.rows(), static_cast<Eigen::Index>(columns[g].size()));
      for (std::size_t m = 0; m < columns[g].size(); ++m)
        members.col(static_cast<Eigen::Index>(m)) = values.col(columns[g][m]);
      const engine::Corridor corridor = engine::MeanSdCorridor(members);
      const auto low = static_cast<Eigen::Index>(traces.size());
      values.col(low) = corridor.low;
      values.col(low + 1) = corridor.high;
      traces.push_back({comparison.groups[g] + " mean − 1 sd", g, formats::ReportOverlay::Trace::Kind::kLow});
      traces.push_back(
          {comparison.groups[g] + " mean + 1 sd", g, formats::ReportOverlay::Trace::Kind::kHigh});
    }
    values.conservativeResize(Eigen::NoChange, static_cast<Eigen::Index>(traces.size()));
  };
  add_corridors(acc, acc_traces, acc_columns);
  report.overlays.push_back(formats::MakeReportOverlay("acc", "Resultant CG acceleration, every test",
                                                       "acceleration (g)", comparison.groups,
                                                       std::move(acc_traces), base, acc));
  if (!omega_traces.empty()) {
    add_corridors(omega, omega_traces, omega_columns);
    report.overlays.push_back(formats::MakeReportOverlay("omega", "Resultant angular velocity, every test",
                                                         "angular velocity (rad/s)", comparison.groups,
                                                         std::move(omega_traces), rotation_base, omega));
  }

  const double step_s = (base(base.size() - 1) - base(0)) / static_cast<double>(base.size() - 1);
  report.overlay_notes.push_back(
      "Every test of series " + comparison.series +
      " with a result (its latest), thin in its variant's colour; " +
      "dashed: each variant's mean ± 1 sd (sample sd) wherever at least 2 of its tests have a sample, the "
      "band "
      "between shaded. " +
      (options.align == OverlayAlignment::kOnset
           ? "Aligned at impact onset: t = 0 at each test's first sample whose resultant CG acceleration "
             "exceeds " +
                 util::FormatNumber(options.onset_threshold_g, 6) + " g (--align onset). "
           : std::string("Aligned at t = 0 as recorded (--align onset aligns at the impact onset). ")) +
      "Common time base: from the earliest to the latest aligned sample in steps of " + Milliseconds(step_s) +
      " (the finest sample interval of the tests, at most " + std::to_string(kOverlayBasePoints) +
      " points), each test linearly interpolated onto it; then reduced for display like the per-test charts, "
      "keeping every bucket's extremes.");
  if (!without_onset.empty())
    report.overlay_notes.push_back("Never above " + util::FormatNumber(options.onset_threshold_g, 6) +
                                   " g, so shown as recorded: " + Joined(without_onset) + ".");
}

// Ratings as the report's tables show them: 3 decimals, times in ms.
std::string Score(double value) { return util::FormatNumber(std::round(value * 1000.0) / 1000.0, 6); }
std::string IntervalMs(double start_s, double end_s) {
  return util::FormatNumber(start_s * 1000.0, 4) + "–" + util::FormatNumber(end_s * 1000.0, 4);
}
const std::vector<std::string> kRatingColumns = {"corridor", "phase", "magnitude", "slope",
                                                 "overall",  "grade", "shift (ms)"};
std::vector<std::string> RatingCells(std::vector<std::string> cells, double corridor, double phase,
                                     double magnitude, double slope, double overall, const std::string& grade,
                                     double shift_s) {
  for (const double score : {corridor, phase, magnitude, slope, overall}) cells.push_back(Score(score));
  cells.push_back(grade);
  cells.push_back(util::FormatNumber(shift_s * 1000.0, 4));
  return cells;
}

// Each variant of the series with 2 or more tests with results: each repeat
// rated against the variant's mean resultant CG acceleration, as `napkin
// correlate --series S --variant V --channel acc_resultant_g` (not stored:
// the report reads the catalogue only).
void AddRepeatability(db::Catalogue& catalogue, const std::string& series,
                      formats::ReportComparison& report) {
  db::TestFilter filter;
  filter.series = {series};
  std::map<std::string, std::size_t> variants;
  for (const db::LabelledResult& result : catalogue.ReadResults(filter, db::ResultSelection::kLatest))
    if (result.variant) ++variants[*result.variant];
  RatingOptions options;
  options.channel = "acc_resultant_g";
  for (const auto& [variant, count] : variants) {
    if (count < 2) continue;
    formats::ReportTable& table = report.repeatability.emplace_back();
    table.heading = "Repeatability of " + variant + ": each repeat against the variant's mean";
    table.columns = {"test", "interval (ms)"};
    table.columns.insert(table.columns.end(), kRatingColumns.begin(), kRatingColumns.end());
    try {
      for (const RatingRow& row : RateVariantRepeats(catalogue, series, variant, options, /*store=*/false)) {
        const engine::Iso18571Rating& r = row.rating;
        table.rows.push_back(RatingCells({row.test_id, IntervalMs(row.start_s, row.end_s)}, r.corridor,
                                         r.phase, r.magnitude, r.slope, r.overall, engine::NameOf(r.grade),
                                         r.shift_s));
      }
    } catch (const InputError& error) {
      table.notes.push_back(error.what());
    }
    table.notes.push_back(
        "ISO/TS 18571 (2024 edition) ratings of each repeat's resultant CG acceleration against the mean of "
        "the "
        "variant's " +
        std::to_string(count) +
        " repeats (their latest results, as recorded, on the overlays' common time base, where every repeat "
        "has a sample), worst first; as napkin correlate --series " +
        series + " --variant " + variant + " --channel acc_resultant_g shows them.");
  }
}

// The series' variants compared as `napkin compare --series S [--baseline
// V]` does (every test of the series with a result, its latest): the
// verdict, the overlaid curves, the table, and each variant's values per
// metric with the 95 % interval of its mean: the one-sample t interval,
// which is engine::PairedComparison's interval of differences from zero.
formats::ReportComparison SeriesComparison(db::Catalogue& catalogue, const std::string& series,
                                           const ReportOptions& options) {
  CompareRequest request;
  request.series = series;
  request.by = CompareBy::kVariant;
  request.baseline = options.baseline;
  request.limits = options.limits;
  // Metrics no test of the series has (the rotation of acceleration-only
  // tests) are left out by BuildComparison: no table rows, no plots.
  const Comparison comparison = BuildComparison(catalogue, request);

  formats::ReportComparison report;
  report.series = series;
  report.verdict = VerdictOf(comparison);
  report.verdict_plots = VerdictPlotsOf(comparison);
  report.limit_tables = LimitTablesOf(comparison);
  AddOverlays(catalogue, comparison, options, report);
  AddRepeatability(catalogue, series, report);
  const db::Table table = ComparisonTable(comparison);
  report.columns = table.columns;
  for (const std::vector<db::Cell>& row : table.rows) {
    std::vector<std::string>& cells = report.rows.emplace_back();
    for (const db::Cell& cell : row) cells.push_back(CellText(cell));
  }
  report.notes.push_back(
      "Every test of series " + series + " with a result (its latest), as napkin compare --series " + series +
      (options.baseline ? " --baseline " + *options.baseline : std::string()) + " shows them; baseline " +
      comparison.baseline +
      "; scale log: ratio of geometric means with its 95 % interval (Welch's t on the logs), diff_pct = "
      "100 (ratio − 1); scale linear: diff = mean − baseline mean with its 95 % interval (Welch's t); the "
      "two-sided p-value of that scale; mdd: the smallest fall and rise these tests detect with 80 % power; "
      "tost_p_value < 0.05: equivalent within ±equivalence_pct %.");
  std::set<std::string> small_groups;
  for (const MetricComparison& metric : comparison.metrics) {
    formats::ReportDistribution& distribution = report.distributions.emplace_back();
    distribution.metric = metric.metric;
    for (std::size_t g = 0; g < metric.groups.size(); ++g) {
      const GroupValues& values = metric.groups[g];
      formats::ReportDistribution::Group& group = distribution.groups.emplace_back();
      group.name = values.group;
      group.values = values.values;
      group.mean = metric.rows[g].description.mean;
      if (values.values.size() < 2) {
        small_groups.insert(values.group);
        continue;
      }
      const engine::MeanDifference interval = engine::PairedComparison(values.values, 1.0);
      if (std::isfinite(interval.ci_low) && std::isfinite(interval.ci_high)) {
        group.ci_low = interval.ci_low;
        group.ci_high = interval.ci_high;
      }
    }
  }
  for (const std::string& group : small_groups)
    report.notes.push_back("Variant " + group +
                           " has fewer than 2 tests with results: no interval and no p-value (—).");
  return report;
}

// The selected tests, ordered by series, variant and test id.
std::vector<db::TestRow> SelectedTests(db::Catalogue& catalogue, const ReportSelection& selection,
                                       const std::vector<db::WhereExpression>& where) {
  // Selected in the catalogue, through its indexes (docs/architecture.md "Catalogues of a million
  // tests"), as every command selects tests.
  std::vector<db::TestRow> tests = catalogue.ReadAllTests(selection.tests);
  if (!where.empty()) {  // the tests whose latest results `query criteria --where` lists
    db::QueryRequest request;
    request.tests = selection.tests;
    request.where = where;
    const db::Table rows = catalogue.Query(db::QueryKind::kCriteria, request);
    std::set<std::string> matching;
    for (const std::vector<db::Cell>& row : rows.rows) matching.insert(std::get<std::string>(row.front()));
    std::erase_if(tests, [&](const db::TestRow& test) { return !matching.count(test.external_id); });
  }
  std::stable_sort(tests.begin(), tests.end(), [](const db::TestRow& a, const db::TestRow& b) {
    return std::tie(a.series, a.variant, a.external_id) < std::tie(b.series, b.variant, b.external_id);
  });
  return tests;
}

// What was asked for, e.g. "series sled, variant foam-a"; "" for every test.
std::string Selection(const ReportSelection& selection) {
  std::vector<std::string> parts;
  const db::TestFilter& tests = selection.tests;
  if (!tests.series.empty()) parts.push_back("series " + Joined(tests.series));
  if (!tests.variants.empty()) parts.push_back("variant " + Joined(tests.variants));
  if (!tests.external_ids.empty()) parts.push_back("test " + Joined(tests.external_ids));
  for (const std::string& expression : selection.where) parts.push_back("where " + expression);
  return Joined(parts);
}

std::string Described(const ReportSelection& selection) {
  return Selection(selection).empty() ? "the catalogue" : Selection(selection);
}

// The report of the selected tests, checked and planned from the catalogue
// (which tests have results, their configs, the comparisons) before
// anything is written; Write then reads one test at a time and streams the
// page (formats::HtmlReportWriter), so its memory does not grow with the
// number of tests.
class CatalogueReport {
 public:
  CatalogueReport(const std::string& db_path, const ReportSelection& selection, const ReportOptions& options)
      : catalogue_(Open(db_path, selection)) {
    for (const std::string& id : selection.tests.external_ids)
      if (!catalogue_.ExistsTestByExternalId(id))
        throw NotFoundError(fmt::format("test '{}' is not in catalogue '{}'.", id, db_path));
    selected_ = SelectedTests(catalogue_, selection, where_);
    if (selected_.empty() && Selection(selection).empty())
      throw InputError("catalogue '" + db_path +
                       "' holds no tests; add some with `napkin import` or `napkin synth` first.");
    if (selected_.empty())
      throw InputError("no test in catalogue '" + db_path + "' matches " + Selection(selection) + ".");

    header_.catalogue = db_path;
    header_.napkin_version = napkin::Version();  // common/version.h: "0.1.0+g1a2b3c4"
    header_.selection = Selection(selection);
    std::map<db::ConfigId, db::ConfigRow> configs;
    std::map<std::string, std::set<std::string>> variants_by_series;
    for (const db::TestRow& record : selected_) {
      const std::optional<db::ConfigId> config_id = FindResult(catalogue_, record.id, Latest{});
      if (!config_id) {
        without_results_.push_back(record.external_id);
        continue;
      }
      auto config = configs.find(*config_id);
      if (config == configs.end())
        config = configs.emplace(*config_id, catalogue_.ReadConfig(*config_id)).first;
      shown_.push_back({&record, *config_id, config->second.name, {}});
      test_ids_.push_back(record.external_id);
      if (record.series && record.variant) variants_by_series[*record.series].insert(*record.variant);
    }
    if (shown_.empty())
      throw InputError("no test of " + Described(selection) +
                       " has results with derived channels yet; run `napkin run` first.");
    for (const auto& [id, config] : configs)
      header_.configs.push_back({config.name, config.config_hash, config.config_json});
    FindRatings(options);
    // Each series of the report with more than one variant is compared.
    for (const auto& [series, variants] : variants_by_series)
      if (variants.size() > 1) comparisons_.push_back(SeriesComparison(catalogue_, series, options));
  }

  // Writes the page through `sink`; the tests shown and the bytes written.
  WrittenReport Write(const formats::HtmlSink& sink) {
    WrittenReport written;
    const formats::HtmlSink counting = [&sink, &written](std::string_view text) {
      sink(text);
      written.bytes = written.bytes.value_or(0) + text.size();
    };
    formats::HtmlReportWriter writer(counting, header_, test_ids_, comparisons_);
    for (const Shown& test : shown_) {
      std::optional<engine::TestSummary> summary = catalogue_.ReadSummary(test.record->id, test.config);
      if (!summary)
        throw InputError("the result of test '" + test.record->external_id +
                         "' disappeared while the report was written; write the report again.");
      const engine::Kinematics kinematics = ReadResultKinematics(catalogue_, test.record->id, test.config);
      formats::ReportTest section =
          formats::MakeReportTest(test.record->external_id, test.record->series, test.record->variant,
                                  test.config_name, std::move(*summary), kinematics);
      AddSalvageCharts(test, section);
      AddRatings(test, kinematics, section);
      writer.AddTest(section);
    }
    writer.Finish();
    written.tests = shown_.size();
    written.without_results = without_results_;
    return written;
  }

 private:
  struct Shown {
    const db::TestRow* record;  // in selected_
    db::ConfigId config;        // of its latest result
    std::string config_name;
    std::vector<db::CorrelationRow> ratings;  // of that result
  };
  // A --model file as read, once (formats::ReadModelFile): its SHA-256 is
  // what stored ratings name, and its curves are drawn from the same bytes.
  struct GivenModel {
    std::string path;
    formats::ModelFile file;
  };

  // Each shown test's stored ratings; every --model must match one.
  void FindRatings(const ReportOptions& options) {
    model_units_ = options.model_units;
    for (const std::string& spec : options.models) {
      const std::string path = ParseModelSpec(spec).path;
      formats::ModelFile file = formats::ReadModelFile(path);
      // Refused before the page is begun, not half-way through it.
      CheckModelUnitsGiven(file, model_units_);
      models_.push_back({path, std::move(file)});
    }
    std::set<std::string> rated;
    for (Shown& test : shown_) {
      test.ratings = catalogue_.ReadCorrelations(test.record->id, test.config);
      for (const db::CorrelationRow& rating : test.ratings)
        if (rating.model_sha256) rated.insert(*rating.model_sha256);
    }
    for (const GivenModel& model : models_)
      if (!rated.count(model.file.sha256))
        throw InputError("model file '" + model.path +
                         "' has no stored rating against the report's tests (their latest results); rate it "
                         "first with `napkin correlate --test T --channel CH --model " +
                         model.path + "`.");
  }

  // Each channel salvage repaired, recorded and repaired overlaid on the
  // result's (shifted) time axis, the fault's interval marked
  // (docs/formats.md "HTML report").
  void AddSalvageCharts(const Shown& test, formats::ReportTest& section) {
    const std::optional<engine::SalvageAudit>& salvage = section.summary.salvage;
    if (!salvage) return;
    const ResultChannels repaired = ReadResultChannels(catalogue_, test.record->id, test.config);
    if (repaired.repaired.empty()) return;
    const engine::TestSignals recorded = catalogue_.ReadTestSignals(test.record->id);
    const std::vector<db::RawChannelInfo> info = catalogue_.ReadRawChannelInfo(test.record->id);
    // time.shift_s is subtracted from every time stamp (engine/channel_conditioning.h).
    const double shift_s =
        section.summary.conditioning.empty() ? 0.0 : section.summary.conditioning.front().time_shift_s;
    Eigen::VectorXd time_s(recorded.size());
    for (Eigen::Index k = 0; k < recorded.size(); ++k) time_s(k) = recorded.TimeAt(k) - shift_s;
    for (std::size_t i = 0; i < salvage->channels.size(); ++i) {
      const engine::SalvagedChannel& channel = salvage->channels[i];
      if (std::find(repaired.repaired.begin(), repaired.repaired.end(), channel.channel) ==
          repaired.repaired.end())
        continue;
      const int column = recorded.FindSlot(channel.channel);
      const auto unit = std::find_if(info.begin(), info.end(), [&](const db::RawChannelInfo& raw) {
        return raw.slot == channel.channel;
      });
      Eigen::MatrixXd traces(recorded.size(), 2);
      traces.col(0) = recorded.samples.col(column);
      traces.col(1) = repaired.signals.samples.col(column);
      formats::ReportChart chart = formats::MakeReportChart(
          "salvage-" + std::to_string(i + 1), channel.channel + ": recorded and repaired (salvage)",
          channel.channel + (unit == info.end() ? std::string() : " (" + unit->unit + ")"),
          {"recorded", "repaired"}, time_s, traces);
      chart.windows.push_back(
          {std::string(engine::NameOf(channel.fault)), channel.t1_s * 1000.0, channel.t2_s * 1000.0});
      section.charts.push_back(std::move(chart));
    }
  }

  // The test's stored ratings as a table, and each against a --model drawn.
  void AddRatings(const Shown& test, const engine::Kinematics& kinematics, formats::ReportTest& section) {
    if (test.ratings.empty()) return;
    formats::ReportTable& table = section.tables.emplace_back();
    table.heading = "ISO/TS 18571 ratings";
    table.columns = {"channel", "against", "edition", "interval (ms)"};
    table.columns.insert(table.columns.end(), kRatingColumns.begin(), kRatingColumns.end());
    for (const db::CorrelationRow& r : test.ratings) {
      table.rows.push_back(RatingCells({r.channel, r.reference, r.edition, IntervalMs(r.start_s, r.end_s)},
                                       r.corridor, r.phase, r.magnitude, r.slope, r.overall, r.grade,
                                       r.shift_s));
      const auto model = std::find_if(models_.begin(), models_.end(), [&](const GivenModel& given) {
        return r.model_sha256 && given.file.sha256 == *r.model_sha256;
      });
      if (model == models_.end()) continue;
      const ChannelCurve channel = ChannelOf(kinematics, r.channel, test.record->external_id);
      const ModelReference curve = LoadModelCurve(model->file, *r.model_column, channel, model_units_);
      const std::string model_name = curve.file_name + ":" + curve.column;
      const RatingPlot plot = PlotRating(channel, curve.series, r.start_s, r.end_s,
                                         *engine::ParseName<engine::Iso18571Edition>(r.edition),
                                         "test '" + test.record->external_id + "' channel " + r.channel,
                                         "model file '" + model->path + "' curve '" + curve.column + "'");
      Eigen::MatrixXd traces(plot.time_s.size(), 6);
      traces << plot.test, plot.model, (plot.test.array() - plot.inner_half_width).matrix(),
          (plot.test.array() + plot.inner_half_width).matrix(),
          (plot.test.array() - plot.outer_half_width).matrix(),
          (plot.test.array() + plot.outer_half_width).matrix();
      formats::ReportChart chart = formats::MakeReportChart(
          "rating-" + std::to_string(section.rating_charts.size() + 1),
          r.channel + ": test against " + model_name + ", overall " + Score(plot.rating.overall) + " (" +
              engine::NameOf(plot.rating.grade) + ")",
          r.channel,
          {test.record->external_id, model_name, "inner corridor −", "inner corridor +", "outer corridor −",
           "outer corridor +"},
          plot.time_s, traces);
      chart.bands = {{2, 3}, {4, 5}};
      section.rating_charts.push_back(std::move(chart));
    }
    table.notes.push_back(
        "Each stored rating of this result (napkin correlate; napkin query correlation lists them): the "
        "test's channel is the reference curve, the other the candidate; scores in [0, 1], overall = 0.4 "
        "corridor + 0.2 (phase + magnitude + slope); grade excellent > 0.94, good > 0.80, fair > 0.58, poor; "
        "shift: the candidate's lag the phase score found. Ratings against a model file given to --model are "
        "drawn below: the test, the model, and the inner (±5 %) and outer (±50 % of the test's largest "
        "|value|) corridors about the test, shaded.");
  }

  // A malformed --where is a usage error before the catalogue is opened.
  db::Catalogue Open(const std::string& db_path, const ReportSelection& selection) {
    for (const std::string& expression : selection.where)
      where_.push_back(ParseWhereExpression(expression, db::QueryFields(db::QueryKind::kCriteria)));
    db::CatalogueOptions read_only;
    read_only.read_only = true;
    return db::Catalogue::Open(db_path, read_only);
  }

  std::vector<db::WhereExpression> where_;  // before catalogue_: Open fills it
  db::Catalogue catalogue_;
  std::vector<db::TestRow> selected_;
  std::vector<Shown> shown_;
  std::vector<std::string> test_ids_;  // of shown_
  std::vector<std::string> without_results_;
  formats::ReportHeader header_;
  std::vector<formats::ReportComparison> comparisons_;
  std::vector<GivenModel> models_;
  std::optional<std::string> model_units_;
};

}  // namespace

OverlayAlignment ParseOverlayAlignment(const std::string& text) {
  if (text == "recorded") return OverlayAlignment::kRecorded;
  if (text == "onset") return OverlayAlignment::kOnset;
  throw UsageError("unknown --align '" + text + "' (use recorded or onset).");
}

WrittenReport WriteCatalogueReport(const std::string& db_path, const ReportSelection& selection,
                                   const std::string& out, const ReportOptions& options) {
  CatalogueReport report(db_path, selection, options);
  WrittenReport written;
  util::WriteFileAtomically(out, [&](util::AtomicFile& file) {
    written = report.Write([&file](std::string_view text) { file.Write(text); });
  });
  written.path = out;
  return written;
}

WrittenReport WriteCatalogueReport(const std::string& db_path, const ReportSelection& selection,
                                   const formats::HtmlSink& sink, const ReportOptions& options) {
  return CatalogueReport(db_path, selection, options).Write(sink);
}

std::string WrittenReportText(const WrittenReport& written) {
  std::string text = written.path == util::kStandardOutputName
                         ? fmt::format("wrote the report to standard output: {}.\n", Tests(written.tests))
                     : written.bytes ? fmt::format("wrote {}: {}, {} bytes.\n", written.path,
                                                   Tests(written.tests), *written.bytes)
                                     : fmt::format("wrote {}: {}.\n", written.path, Tests(written.tests));
  if (!written.without_results.empty())
    text += fmt::format("left out {} without results ({}); run `napkin run` first.\n",
                        Tests(written.without_results.size()), Joined(written.without_results));
  return text;
}

}  // namespace napkin::app
