#pragma once
// Test against model, test against test, and the repeatability of a
// variant: ISO/TS 18571 ratings (engine/iso18571.h; docs/algorithms.md "Test
// against model: ISO/TS 18571") of one derived channel of tests' results,
// as `napkin correlate` and the report make them (docs/formats.md
// "Correlation ratings"). Ratings are stored in the catalogue
// (db::Catalogue::WriteCorrelation) and listed by `napkin query correlation`.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "app/result_selection.h"
#include "db/catalogue.h"
#include "engine/iso18571.h"
#include "engine/overlay.h"
#include "formats/model_curves.h"

namespace napkin::app {

// The channels a rating takes, by their derived-channel names
// (docs/formats.md "Derived channels"): every column of the derived-channel
// CSV but time_s and the quaternion, and the resultants acc_resultant_g,
// omega_resultant_radps, alpha_resultant_radps2.
std::vector<std::string> CorrelationChannelNames();

// A channel of a test's result: its values in SI on the result's time axis.
struct ChannelCurve {
  std::string name;              // e.g. "acc_resultant_g"
  formats::Dimension dimension;  // of the SI values
  double display_per_si = 1.0;   // to the unit the name ends in (g: 1 / 9.80665)
  engine::TimeSeries series;     // SI
};

// Throws UsageError for a name not in CorrelationChannelNames() (listing them).
void CheckCorrelationChannel(const std::string& channel);

// The channel `channel` of `kinematics` (ReadResultKinematics). Throws
// InputError naming the test when it does not have the channel (an
// acceleration-only test has no rotation).
ChannelCurve ChannelOf(const engine::Kinematics& kinematics, const std::string& channel,
                       const std::string& test_id);

// A model's curve (formats/model_curves.h) chosen for a channel.
struct ModelReference {
  std::string file_name;      // the file's name without its folder
  std::string sha256;         // of the bytes the curve was read from (formats::ModelFile)
  std::string column;         // the curve's name in the file
  engine::TimeSeries series;  // SI, time in s
  // The --model-units its numbers were read in (an LS-DYNA curve, whose numbers carry none);
  // empty for a CSV curve, whose header gives its units.
  std::optional<std::string> units;
};

// `--model FILE[:COLUMN]` for `channel`: the file (a model CSV, an LS-DYNA
// keyword file with *DEFINE_CURVE, or an ASCII nodout; by its content) and
// its curve named COLUMN (for keyword curves also the LCID alone); without
// COLUMN, the file's one curve, else the one named like the channel. Curves
// of a known dimension must have the channel's; keyword curves are taken
// as the channel's quantity in `units`. Throws InputError naming the file
// (and the column) when it cannot be read, has no such curve or a curve of
// another quantity; UsageError when an LS-DYNA file comes without `units`
// (`--model-units`).
ModelReference LoadModelCurve(const std::string& spec, const ChannelCurve& channel,
                              const std::optional<std::string>& units);
// The same from a file already read (formats::ReadModelFile) and COLUMN
// (empty: none given).
ModelReference LoadModelCurve(const formats::ModelFile& file, const std::string& column,
                              const ChannelCurve& channel, const std::optional<std::string>& units);

// Throws the UsageError of LoadModelCurve when `file` is an LS-DYNA file
// and `units` is not given: checked before a command writes anything.
void CheckModelUnitsGiven(const formats::ModelFile& file, const std::optional<std::string>& units);

// The parameters of a rating as the user gives them.
// The least part of the reference curve's time span the common span of the two curves must cover
// for a rating without --start and --end (docs/formats.md "Correlation ratings").
inline constexpr double kMinCurveCoverage = 0.5;

struct RatingOptions {
  std::string channel;
  std::optional<double> start_s, end_s;  // the evaluation interval; open: the curves' common span
  engine::Iso18571Edition edition = engine::Iso18571Edition::k2024;
};

// RatingOptions from option text: `start`, `end` (seconds; empty: open)
// must be finite numbers, end above start; `edition` "2014" or "2024".
// Throws UsageError naming the option.
RatingOptions ParseRatingOptions(const std::string& channel, const std::string& start, const std::string& end,
                                 const std::string& edition);

// One rating as `correlate` prints and the catalogue stores it.
struct RatingRow {
  std::string test_id;
  std::string channel;
  std::string reference;  // the model file and column, the reference test, or "mean of V"
  engine::Iso18571Edition edition;
  double start_s = 0.0, end_s = 0.0;
  engine::Iso18571Rating rating;
};

// The three forms of `napkin correlate`; each rating is stored (the test's
// result under `choice`) and returned. Throws InputError naming the test,
// file or channel for anything missing or unreadable (ResultOf, LoadModelCurve,
// ChannelOf, the engine's interval checks).
RatingRow RateAgainstModel(db::Catalogue& catalogue, const std::string& test_id,
                           const std::string& model_spec, const std::optional<std::string>& model_units,
                           const RatingOptions& options, const ResultChoice& choice = Latest{});
RatingRow RateAgainstTest(db::Catalogue& catalogue, const std::string& test_id,
                          const std::string& reference_test_id, const RatingOptions& options,
                          const ResultChoice& choice = Latest{});

// Each repeat of variant `variant` of series `series` (every test of it
// with a result, its latest) against the variant's mean curve: the tests'
// channels resampled onto the overlays' common time base
// (engine::CommonTimeBase, as the report's overlaid curves, time as
// recorded) and averaged where every repeat has a sample; each repeat is
// then rated against that mean. Rows worst first (overall ascending, then
// test id). `store`: write each rating (the report computes without).
// Throws InputError when the variant has fewer than 2 tests with results.
std::vector<RatingRow> RateVariantRepeats(db::Catalogue& catalogue, const std::string& series,
                                          const std::string& variant, const RatingOptions& options,
                                          bool store = true);

// The rows as `correlate` prints them (columns as `query correlation`'s of
// the same names): test_id, channel, reference, edition, start_s, end_s,
// corridor, phase, magnitude, slope, overall, grade, shift_s.
db::Table RatingTable(const std::vector<RatingRow>& rows);

// A stored rating against a model drawn again (the report): the test's and
// the model's curves on the rating's time base, in the channel's display
// unit, the corridors about the test's curve, and the rating.
struct RatingPlot {
  Eigen::VectorXd time_s;
  Eigen::VectorXd test, model;
  double inner_half_width = 0.0, outer_half_width = 0.0;  // display unit
  engine::Iso18571Rating rating;
};
RatingPlot PlotRating(const ChannelCurve& test, const engine::TimeSeries& model, double start_s, double end_s,
                      engine::Iso18571Edition edition, const std::string& test_name,
                      const std::string& model_name);

// The SHA-256 of a model file named in `--model FILE[:COLUMN]` and that
// spec's column (empty when none): what the report matches stored ratings by.
struct ModelSpec {
  std::string path;
  std::string column;
};
ModelSpec ParseModelSpec(const std::string& spec);

}  // namespace napkin::app
