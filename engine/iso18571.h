#pragma once
// The objective rating of ISO/TS 18571 ("Road vehicles — Objective rating
// metric for non-ambiguous signals", first edition 2014, second edition 2024;
// docs/algorithms.md "Test against model: ISO/TS 18571"): how well a
// candidate curve (a model's, or another test's) reproduces a reference
// curve (the test's), as a corridor, a phase, a magnitude and a slope score
// in [0, 1], their weighted sum (the overall rating) and its grade.
//
// Pure functions, no I/O: the commands (`napkin correlate`), the Python
// module (napkin.iso18571) and the report call these.
#include <Eigen/Core>
#include <array>
#include <optional>
#include <span>
#include <string_view>

#include "engine/overlay.h"
#include "engine/vocabulary.h"

namespace napkin::engine {

enum class Iso18571Edition {
  k2014,  // first edition (ISO/TS 18571:2014): no dynamic-time-warping window
  k2024,  // second edition (ISO/TS 18571:2024): window of 10 % of the interval (the default)
};
inline constexpr std::array<NamedValue<Iso18571Edition>, 2> kIso18571EditionNames{
    {{Iso18571Edition::k2014, "2014"}, {Iso18571Edition::k2024, "2024"}}};
inline constexpr std::array<Iso18571Edition, 2> kIso18571Editions = ValuesOf(kIso18571EditionNames);
constexpr const auto& NamesOf(Iso18571Edition) { return kIso18571EditionNames; }

// Every parameter of the metric (docs/algorithms.md, table "Parameters").
// ForEdition() gives the standard's values; the fields stay open so a study
// can vary one (Check() refuses values the formulas cannot take).
struct Iso18571Parameters {
  Iso18571Edition edition = Iso18571Edition::k2024;
  // Corridor score: inner and outer corridor half widths a0 T_norm and
  // b0 T_norm about the reference (T_norm = max |reference|), exponent kz.
  double a0 = 0.05;
  double b0 = 0.5;
  double kz = 2.0;
  // Phase score: the candidate is shifted by up to floor(max_shift N) samples
  // either way; shifts of max_shift N or more score 0; exponent kp.
  double max_shift = 0.2;
  double kp = 1.0;
  // Magnitude score (EEARTH magnitude error after dynamic time warping):
  // errors of eps_m or more score 0; exponent km. The warping path stays
  // within |i - j| < ceil(dtw_window n) (the Sakoe-Chiba band); nullopt
  // warps without a window.
  double eps_m = 0.5;
  double km = 1.0;
  std::optional<double> dtw_window = 0.1;
  // Slope score (EEARTH slope error of the smoothed derivatives): errors of
  // eps_s or more score 0; exponent ks.
  double eps_s = 2.0;
  double ks = 1.0;
  // Weights of the overall rating (sum 1).
  double w_corridor = 0.4;
  double w_phase = 0.2;
  double w_magnitude = 0.2;
  double w_slope = 0.2;
  // The common time base both curves are resampled onto (the standard asks
  // for 10 kHz); used by Iso18571RateCurves only.
  double rate_hz = 10000.0;

  static Iso18571Parameters ForEdition(Iso18571Edition edition);
  // Throws InputError naming the parameter out of its range.
  void Check() const;
};

// The grade of an overall rating R (the standard's clause 7):
// excellent R > 0.94, good 0.80 < R <= 0.94, fair 0.58 < R <= 0.80, poor.
enum class Iso18571Grade { kExcellent, kGood, kFair, kPoor };
inline constexpr std::array<NamedValue<Iso18571Grade>, 4> kIso18571GradeNames{
    {{Iso18571Grade::kExcellent, "excellent"},
     {Iso18571Grade::kGood, "good"},
     {Iso18571Grade::kFair, "fair"},
     {Iso18571Grade::kPoor, "poor"}}};
inline constexpr std::array<Iso18571Grade, 4> kIso18571Grades = ValuesOf(kIso18571GradeNames);
constexpr const auto& NamesOf(Iso18571Grade) { return kIso18571GradeNames; }
Iso18571Grade GradeOf(double overall);

struct Iso18571Rating {
  double corridor = 0.0;   // Z
  double phase = 0.0;      // E_P
  double magnitude = 0.0;  // E_M
  double slope = 0.0;      // E_S
  double overall = 0.0;    // R = w_Z Z + w_P E_P + w_M E_M + w_S E_S
  Iso18571Grade grade = Iso18571Grade::kPoor;
  // The shift of the candidate that correlates best with the reference, in
  // samples and seconds: positive when the candidate lags (its features come
  // later), so the candidate was moved earlier by shift_samples.
  long shift_samples = 0;
  double shift_s = 0.0;
  double correlation = 0.0;      // Pearson coefficient at that shift (rho_E)
  double magnitude_error = 0.0;  // eps_mag (infinity for an all-zero warped reference)
  double slope_error = 0.0;      // eps_slope (likewise)
  // The corridors' half widths a0 T_norm and b0 T_norm (the report shades
  // reference +- each).
  double inner_half_width = 0.0;
  double outer_half_width = 0.0;
  long samples = 0;  // N, samples of the evaluation interval
};

// Rates `candidate` against `reference`, two curves already on one time base
// of step dt_s covering exactly the evaluation interval (same length, at
// least 9 samples, finite). Throws InputError otherwise, naming the curve and
// sample, and for bad parameters.
// Cost: O(N max_shift N) for the phase search; the warping visits the band
// cells whose accumulated cost can still beat the unwarped alignment's
// (all of the band where both curves are flat), O(N window N) at worst;
// memory O(N). About 24 pairs of 10,000 samples a second on one core
// (docs/algorithms.md).
Iso18571Rating Iso18571Rate(std::span<const double> reference, std::span<const double> candidate, double dt_s,
                            const Iso18571Parameters& parameters = {});

// The evaluation interval [start_s, end_s]; an end left open is the common
// part of the two curves' time ranges.
struct Iso18571Interval {
  std::optional<double> start_s;
  std::optional<double> end_s;
};

// Rates two curves on time bases of their own (each strictly increasing):
// both are resampled by linear interpolation (ResampleOnto) onto
// start_s, start_s + 1 / rate_hz, ... <= end_s. Throws InputError when the
// interval is empty, reaches outside either curve, or holds fewer than 9
// samples. `reference_name` and `candidate_name` name the curves in errors.
Iso18571Rating Iso18571RateCurves(const TimeSeries& reference, const TimeSeries& candidate,
                                  const Iso18571Interval& interval = {},
                                  const Iso18571Parameters& parameters = {},
                                  std::string_view reference_name = "the reference",
                                  std::string_view candidate_name = "the candidate");

// The time base Iso18571RateCurves resamples onto: start_s, start_s +
// 1 / rate_hz, ... <= end_s (to 1e-6 of a step); what the report draws a
// rating on.
Eigen::VectorXd Iso18571TimeBase(double start_s, double end_s, double rate_hz);

// The pieces, for tests and the report. Each takes curves of one length N.
// Corridor score Z (mean over the samples of the corridor fit).
double Iso18571Corridor(std::span<const double> reference, std::span<const double> candidate,
                        const Iso18571Parameters& parameters);
// The warped curves' EEARTH magnitude error sum |C_w - T_w| / sum |T_w| along
// the optimal warping path (squared-difference local cost, steps (1,0),
// (0,1), (1,1) of unit weight; ties prefer the diagonal, then the step that
// advances the reference, then the candidate). `window`: band half width
// (|i - j| <= window), nullopt for none.
double Iso18571MagnitudeError(std::span<const double> reference, std::span<const double> candidate,
                              std::optional<long> window);
// The same, by the full cost matrix and a backtrack: O(N^2) memory, the
// reference the tests compare the pruned band with.
double Iso18571MagnitudeErrorFullMatrix(std::span<const double> reference, std::span<const double> candidate,
                                        std::optional<long> window);
// The smoothed derivative of the slope score: central differences (one-sided
// at the ends) over dt_s, then a centred moving average of 9 samples (1, 3, 5
// and 7 at the first and last four samples).
Eigen::VectorXd Iso18571SmoothedDerivative(std::span<const double> values, double dt_s);

}  // namespace napkin::engine
