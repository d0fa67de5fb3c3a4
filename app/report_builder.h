#pragma once
// The HTML report of a catalogue's tests (docs/formats.md "HTML report"), as
// `napkin report` and `napkin demo` write it.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "db/catalogue.h"
#include "formats/html_report.h"

namespace napkin::app {

// Which tests the report shows; empty members do not filter. A test matches
// every member (within one member any of the names); `where` holds
// `--where` expressions over the `query criteria` fields.
struct ReportSelection {
  db::TestFilter tests;            // --series, --variant, --test (each repeatable)
  std::vector<std::string> where;  // --where over the latest results (query criteria's fields)
};

// Where the overlaid curves of a series put each test's t = 0
// (docs/formats.md "HTML report"): as recorded, or at its impact onset.
enum class OverlayAlignment { kRecorded, kOnset };

// "recorded" or "onset"; throws UsageError otherwise.
OverlayAlignment ParseOverlayAlignment(const std::string& text);

// The default onset threshold: 5 g of resultant CG acceleration.
inline constexpr double kDefaultOnsetThresholdG = 5.0;

// At most this many points on the overlays' common time base
// (engine::CommonTimeBase), which holds one column per test of the series;
// also the base of a variant's mean curve (app/correlation.h).
inline constexpr std::ptrdiff_t kOverlayBasePoints = 10000;

// How the comparisons of the report are made and drawn.
struct ReportOptions {
  // The variant every compared series is compared with (each must have it);
  // default: as `napkin compare`, the first variant in name order.
  std::optional<std::string> baseline;
  OverlayAlignment align = OverlayAlignment::kRecorded;
  // kOnset: t = 0 at each test's first sample whose resultant CG
  // acceleration exceeds this many g.
  double onset_threshold_g = kDefaultOnsetThresholdG;
  // Limit sets the verdict, its pictures and the compare table check
  // (app/limits.h): each a preset name of config/limits or a file.
  std::vector<std::string> limits;
  // Model files (FILE[:COLUMN], app/correlation.h) whose stored ratings
  // against the report's tests are drawn: the test and the model with the
  // ISO/TS 18571 corridors; each must match a stored rating of a shown test.
  std::vector<std::string> models;
  std::optional<std::string> model_units;  // LENGTH,TIME,MASS of LS-DYNA model files
};

struct WrittenReport {
  std::string path;
  std::size_t tests = 0;                     // tests shown
  std::optional<std::uintmax_t> bytes;       // bytes written (none when nothing was)
  std::vector<std::string> without_results;  // selected tests left out: no results yet
};

// Writes the report of the selected tests of the catalogue at `db_path`
// (opened read-only) to `out`: each test's latest result, and the
// comparison of each series with more than one variant (its verdict,
// app/verdict.h, overlaid curves, as `options` say, and the repeatability
// of each variant, app/correlation.h RateVariantRepeats), each test's stored
// ISO/TS 18571 ratings and those against `options.models` drawn. Throws UsageError
// for a malformed `where` (before the catalogue is opened) or a baseline a
// compared series does not have, InputError (one
// sentence) for an unknown test id, a selection matching no test, or no test
// with results.
WrittenReport WriteCatalogueReport(const std::string& db_path, const ReportSelection& selection,
                                   const std::string& out, const ReportOptions& options = {});

// The same page written through `sink` (a destination the caller opened,
// e.g. standard output), after the same checks; `path` of the answer is
// empty. The page streams: one test is read and held at a time.
WrittenReport WriteCatalogueReport(const std::string& db_path, const ReportSelection& selection,
                                   const formats::HtmlSink& sink, const ReportOptions& options = {});

// "wrote FILE: N tests, B bytes." (standard output: "wrote the report to
// standard output: N tests.") and, when some were left out, a second line
// naming them; each line ends with a newline.
std::string WrittenReportText(const WrittenReport& written);

}  // namespace napkin::app
