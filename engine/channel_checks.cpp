// The per-channel checks of the raw signals (engine/screening.h
// ScreenSignals; docs/algorithms.md "Screening"): non-finite samples,
// plausibility, flat channels, saturation, spikes and bias.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "engine/cancellation.h"
#include "engine/kinematics_completer.h"
#include "engine/screening.h"
#include "engine/screening_text.h"
#include "engine/units.h"

namespace napkin::engine {
namespace {

using Eigen::Index;
using internal::MakeFinding;
using internal::Median;
using internal::Number;

// A spike must stand this many robust standard deviations (1.4826 MAD) of
// the local second differences above them, so ringing and sharp real
// pulses, whose neighbours vary as much, are not mistaken for spikes.
constexpr double kSpikeRobustFactor = 10.0;
// Half-width (samples) of the window of the robust local scale.
constexpr Index kSpikeScaleHalfWindow = 50;

// Saturation: the run must sit at the larger-magnitude end of the channel
// (at least this fraction of its largest |value|) and away from the
// channel's typical level (median) by this fraction of its range, so the
// resting level of a channel that only swings the other way is no "clip".
constexpr double kSaturationMagnitudeFraction = 0.5;
constexpr double kSaturationRangeFraction = 0.25;

// Bias without pre-impact data: the start level is the mean over the first
// kStartWindowS (at least kStartMinSamples samples, at most a quarter of the
// record); the other channels of the kind count as "starting near zero"
// when within half the bias limit of their expected reading.
constexpr double kStartWindowS = 0.001;
constexpr Index kStartMinSamples = 5;
constexpr Index kPreImpactMinSamples = 5;

std::optional<Finding> CheckNonFinite(const Sensor& sensor, const TestSignals& signals,
                                      const Eigen::Ref<const Eigen::VectorXd>& x) {
  // A finite sum has no infinite or NaN term (either would make it
  // non-finite): one vectorised pass decides a clean channel; an overflowing
  // sum of finite samples only takes the exact loop below.
  if (std::isfinite(x.sum())) return std::nullopt;
  Index count = 0, first = -1, last = -1;
  for (Index k = 0; k < x.size(); ++k) {
    if (std::isfinite(x(k))) continue;
    if (first < 0) first = k;
    last = k;
    ++count;
  }
  if (count == 0) return std::nullopt;
  std::ostringstream detail;
  detail << "channel " << sensor.slot << " has " << count << " non-finite sample" << (count > 1 ? "s" : "")
         << " (a dropout), the first at sample " << first << " (t = " << Number(signals.TimeAt(first), 6)
         << " s)";
  if (last != first)
    detail << " and the last at sample " << last << " (t = " << Number(signals.TimeAt(last), 6) << " s)";
  detail << ".";
  return MakeFinding(Check::kNonFinite, sensor.slot, Severity::kError, detail.str());
}

// Physical plausibility of a raw channel (ProcessingConfig::plausibility):
// the largest |value| beyond the limit of its kind, in g or rad/s.
// A channel's largest and smallest sample, found once for the checks below.
struct Extremes {
  double top = 0.0, bottom = 0.0;
};

std::optional<Finding> CheckPlausible(const Sensor& sensor, const TestSignals& signals,
                                      const Eigen::Ref<const Eigen::VectorXd>& x, Extremes extremes,
                                      const PlausibilityConfig& limits) {
  if (x.size() == 0) return std::nullopt;
  const bool linear = sensor.kind == SensorKind::kLinear;
  const double limit = linear ? limits.max_acceleration_g : limits.max_angular_velocity_radps;
  // The largest |value| from the extremes (vectorised, no index): the
  // sample is looked for only when it is beyond the limit.
  const double largest_si = std::max(extremes.top, -extremes.bottom) * sensor.si_per_unit;
  if (!(std::abs(linear ? largest_si / kStandardGravity : largest_si) > limit)) return std::nullopt;
  Index worst = 0;
  x.cwiseAbs().maxCoeff(&worst);
  const double value_si = x(worst) * sensor.si_per_unit;
  const double value = linear ? value_si / kStandardGravity : value_si;
  if (!(std::abs(value) > limit)) return std::nullopt;
  const char* unit = linear ? " g" : " rad/s";
  // Read from a file, the sample's row too (issue 29 point 11).
  const std::optional<std::int64_t> row = signals.FileRowOf(worst);
  return MakeFinding(Check::kImplausible, sensor.slot, Severity::kError,
                     "channel " + sensor.slot + " reads " + Number(value, 6) + unit + " at sample " +
                         std::to_string(worst) + " (" + (row ? "row " + std::to_string(*row) + ", " : "") +
                         "t = " + Number(signals.TimeAt(worst), 6) +
                         " s), beyond the plausibility limit of " + Number(limit, 6) + unit +
                         ": a corrupt sample or a wrong unit; correct the data (or raise "
                         "plausibility limits in the processing config).");
}

// The pre-scans of the checks below: counts over a channel's samples, in
// loops without branches. GCC vectorizes their comparisons of doubles into
// 64-bit counts with AVX2 only (SSE2 has no vector type for them), so they
// are compiled for both and chosen when the program loads
// (NAPKIN_SAMPLE_LOOP_CLONES, engine/kinematics_completer.h): counts are
// integers, the same whichever clone runs.
struct ExtremeCounts {
  Index at_top = 0, at_bottom = 0;
};

NAPKIN_SAMPLE_LOOP_CLONES ExtremeCounts CountAtExtremes(const double* samples, Index n, double top,
                                                        double bottom, double tolerance) {
  std::int64_t at_top = 0, at_bottom = 0;
  for (Index k = 0; k < n; ++k) {
    at_top += std::abs(samples[k] - top) <= tolerance;
    at_bottom += std::abs(samples[k] - bottom) <= tolerance;
  }
  return {at_top, at_bottom};
}

// Samples 1 .. n - 2 whose jumps from and to their neighbours are both
// beyond `size` and of one sign (CheckSpikes' candidates, its own test).
NAPKIN_SAMPLE_LOOP_CLONES Index CountSpikeCandidates(const double* samples, Index n, double size) {
  std::int64_t candidates = 0;
  for (Index k = 1; k + 1 < n; ++k) {
    const double jump_back = samples[k] - samples[k - 1], jump_ahead = samples[k] - samples[k + 1];
    candidates += static_cast<std::int64_t>(!(jump_back * jump_ahead <= 0.0)) &
                  static_cast<std::int64_t>(!(std::min(std::abs(jump_back), std::abs(jump_ahead)) <= size));
  }
  return candidates;
}

std::optional<Finding> CheckSaturation(const Sensor& sensor, const TestSignals& signals,
                                       const Eigen::Ref<const Eigen::VectorXd>& x, Extremes extremes,
                                       int run_samples) {
  const double top = extremes.top, bottom = extremes.bottom;
  const double range = top - bottom;
  if (!(range > 0.0)) return std::nullopt;
  const double magnitude = std::max(std::abs(top), std::abs(bottom));
  // Longest run of samples equal to each extreme (a clipped ADC returns one
  // code; allow round-off of a unit conversion). Runs come first: an
  // unclipped channel has no run of run_samples, and then the median (a
  // copy and a selection of the whole channel) is not needed.
  const double tolerance = 1e-12 * magnitude;
  // A run of L samples at an extreme needs L samples at it: counted first in
  // a branch-free (vectorised) pass, which decides an unclipped channel.
  const ExtremeCounts counts = CountAtExtremes(x.data(), x.size(), top, bottom, tolerance);
  if (counts.at_top < run_samples && counts.at_bottom < run_samples) return std::nullopt;
  struct Run {
    Index length = 0, end = 0;
  };
  // Both extremes in one pass over the channel.
  Run top_run, bottom_run;
  Index top_count = 0, bottom_count = 0;
  for (Index k = 0; k < x.size(); ++k) {
    top_count = std::abs(x(k) - top) <= tolerance ? top_count + 1 : 0;
    bottom_count = std::abs(x(k) - bottom) <= tolerance ? bottom_count + 1 : 0;
    if (top_count > top_run.length) top_run = {top_count, k};
    if (bottom_count > bottom_run.length) bottom_run = {bottom_count, k};
  }
  if (top_run.length < run_samples && bottom_run.length < run_samples) return std::nullopt;
  const double median = Median(std::vector<double>(x.data(), x.data() + x.size()));
  std::optional<Finding> worst;
  Index worst_run = 0;
  for (const double extreme : {top, bottom}) {
    if (std::abs(extreme) < kSaturationMagnitudeFraction * magnitude) continue;
    if (std::abs(extreme - median) < kSaturationRangeFraction * range) continue;
    const Index best_run = (extreme == top ? top_run : bottom_run).length;
    const Index best_end = (extreme == top ? top_run : bottom_run).end;
    if (best_run < run_samples || best_run <= worst_run) continue;
    worst_run = best_run;
    const Index start = best_end - best_run + 1;
    std::ostringstream detail;
    detail << "channel " << sensor.slot << " stays at its " << (extreme == top ? "maximum " : "minimum ")
           << Number(extreme) << " " << sensor.unit << " for " << best_run
           << " consecutive samples from t = " << Number(signals.TimeAt(start), 6)
           << " s, a flat top that indicates a clipped (saturated) signal.";
    worst = MakeFinding(Check::kSaturation, sensor.slot, Severity::kError, detail.str());
  }
  return worst;
}

std::optional<Finding> CheckSpikes(const Sensor& sensor, const TestSignals& signals,
                                   const Eigen::Ref<const Eigen::VectorXd>& x,
                                   const ScreeningConfig& config) {
  const Index n = x.size();
  if (n < 3) return std::nullopt;
  const double size = InChannelUnits(sensor, config.spike_size_g, config.spike_size_radps);
  // A candidate (both jumps large and of one sign) is rare, and whether the
  // jumps of noise share a sign is a coin toss the processor cannot predict:
  // a branch-free (vectorised) pass counts the candidates with the loop's
  // own test, and a channel with none needs no more.
  if (CountSpikeCandidates(x.data(), n, size) == 0) return std::nullopt;
  Index count = 0, largest_at = -1;
  double largest = 0.0;
  std::vector<double> window;
  for (Index k = 1; k + 1 < n; ++k) {
    const double jump_back = x(k) - x(k - 1), jump_ahead = x(k) - x(k + 1);
    // A spike leaves and returns: both jumps large and of one sign.
    if (jump_back * jump_ahead <= 0.0 || std::min(std::abs(jump_back), std::abs(jump_ahead)) <= size)
      continue;
    const double second_difference = 0.5 * (jump_back + jump_ahead);
    // Robust local scale of the second differences around k (k excluded).
    window.clear();
    const Index lo = std::max<Index>(1, k - kSpikeScaleHalfWindow);
    const Index hi = std::min<Index>(n - 2, k + kSpikeScaleHalfWindow);
    for (Index j = lo; j <= hi; ++j)
      if (j != k) window.push_back(std::abs(x(j) - 0.5 * (x(j - 1) + x(j + 1))));
    const double scale = 1.4826 * MedianInPlace(window);  // no copy per candidate sample
    if (std::abs(second_difference) <= kSpikeRobustFactor * scale) continue;
    ++count;
    if (std::abs(second_difference) > largest) {
      largest = std::abs(second_difference);
      largest_at = k;
    }
  }
  if (count == 0) return std::nullopt;
  std::ostringstream detail;
  detail << "channel " << sensor.slot << " has " << count << " one-sample spike" << (count > 1 ? "s" : "")
         << " above " << Number(size) << " " << sensor.unit << ", the largest " << Number(largest) << " "
         << sensor.unit << " at sample " << largest_at << " (t = " << Number(signals.TimeAt(largest_at), 6)
         << " s).";
  return MakeFinding(Check::kSpike, sensor.slot, Severity::kWarning, detail.str());
}

// Reading a sensor should show at rest: zero for a zeroed linear
// accelerometer, n . omega0 for an angular-rate sensor.
double ExpectedStartReading(const Sensor& sensor, const InitialState& initial) {
  if (sensor.kind == SensorKind::kLinear) return 0.0;
  return sensor.axis_body.dot(initial.omega_body_radps) / sensor.si_per_unit;
}

// Bias (report sections 2.2 and 3.4: "checked for bias error"). With
// pre-impact data (t < 0 after the shift, >= kPreImpactMinSamples samples):
// each channel's pre-impact mean against the limit. Without, a crash record
// starts at or just before the impact, when every channel should still read
// about zero: a channel that starts beyond the limit while every other
// channel of its kind starts near zero carries an offset (when the others
// do not start near zero the head is already moving and the start level
// says nothing).
void CheckBias(const ArrayGeometry& array, const std::vector<int>& columns, const TestSignals& signals,
               const InitialState& initial, const ProcessingConfig& config, std::vector<Finding>& findings) {
  const Index n = signals.size();
  const double dt = signals.dt_s;
  Index pre_impact = 0;
  while (pre_impact < n && signals.TimeAt(pre_impact) - config.time.shift_s < -1e-9 * dt) ++pre_impact;
  const bool has_pre_impact = pre_impact >= kPreImpactMinSamples;
  const Index start_count =
      has_pre_impact ? pre_impact
                     : std::min<Index>(std::max<Index>(kStartMinSamples, std::llround(kStartWindowS / dt)),
                                       std::max<Index>(1, n / 4));
  if (n == 0) return;
  std::vector<double> offset(array.sensors.size(), 0.0);
  for (std::size_t i = 0; i < array.sensors.size(); ++i) {
    const Sensor& sensor = array.sensors[i];
    offset[i] =
        signals.samples.col(columns[i]).head(start_count).mean() - ExpectedStartReading(sensor, initial);
  }
  // Whether conditioning will subtract the offset (ApplyConditioning).
  const bool removed =
      config.bias.mode == BiasMode::kWindow ||
      (config.bias.mode == BiasMode::kAuto && has_pre_impact &&
       static_cast<double>(pre_impact) * dt >= config.bias.auto_min_pre_impact_s * (1.0 - 1e-9));
  for (std::size_t i = 0; i < array.sensors.size(); ++i) {
    const Sensor& sensor = array.sensors[i];
    const double limit =
        InChannelUnits(sensor, config.screening.bias_limit_g, config.screening.bias_limit_radps);
    if (!(std::abs(offset[i]) > limit)) continue;
    std::ostringstream detail;
    if (has_pre_impact) {
      detail << "channel " << sensor.slot << " has a pre-impact mean of " << Number(offset[i]) << " "
             << sensor.unit << " over " << pre_impact << " samples before t = 0, beyond the " << Number(limit)
             << " " << sensor.unit << " bias limit"
             << (removed ? " (the configured bias removal subtracts it)."
                         : " (the configured bias removal does not).");
    } else {
      bool others_quiet = true;
      int others = 0;
      for (std::size_t j = 0; j < array.sensors.size(); ++j) {
        const Sensor& other = array.sensors[j];
        if (j == i || other.kind != sensor.kind) continue;
        ++others;
        const double other_limit =
            InChannelUnits(other, config.screening.bias_limit_g, config.screening.bias_limit_radps);
        if (std::abs(offset[j]) > 0.5 * other_limit) others_quiet = false;
      }
      if (others == 0 || !others_quiet) continue;
      detail << "channel " << sensor.slot << " starts at " << Number(offset[i]) << " " << sensor.unit
             << (sensor.kind == SensorKind::kLinear ? "" : " off its initial-rate reading")
             << " (mean of the first " << start_count
             << " samples, no pre-impact data) while the other channels start near zero: a "
             << "zero offset beyond the " << Number(limit) << " " << sensor.unit << " bias limit that "
             << (removed ? "the configured bias window subtracts." : "no bias removal corrects.");
    }
    findings.push_back(MakeFinding(Check::kBias, sensor.slot, Severity::kWarning, detail.str()));
  }
}

}  // namespace

std::vector<Finding> ScreenSignals(const ArrayGeometry& array, const TestSignals& raw_signals,
                                   const InitialState& initial, const ProcessingConfig& config,
                                   const std::atomic<bool>* cancel) {
  std::vector<Finding> findings;
  std::vector<int> columns(array.sensors.size(), -1);
  bool complete = true;
  for (std::size_t i = 0; i < array.sensors.size(); ++i) {
    const Sensor& sensor = array.sensors[i];
    columns[i] = raw_signals.FindSlot(sensor.slot);
    if (columns[i] < 0 || columns[i] >= raw_signals.samples.cols()) {
      findings.push_back(MakeFinding(
          Check::kMissing, sensor.slot, Severity::kError,
          "the signals have no channel for slot " + sensor.slot + " of array " + array.name + "."));
      complete = false;
    }
  }
  if (!complete) return findings;

  bool all_finite = true;
  for (std::size_t i = 0; i < array.sensors.size(); ++i) {
    ThrowIfCancelled(cancel);  // each channel's checks take milliseconds of a long record
    const Sensor& sensor = array.sensors[i];
    const auto x = raw_signals.samples.col(columns[i]);
    if (std::optional<Finding> finding = CheckNonFinite(sensor, raw_signals, x)) {
      findings.push_back(std::move(*finding));
      all_finite = false;
      continue;
    }
    if (x.size() == 0) continue;
    const Extremes extremes{x.maxCoeff(), x.minCoeff()};
    if (std::optional<Finding> finding =
            CheckPlausible(sensor, raw_signals, x, extremes, config.plausibility))
      findings.push_back(std::move(*finding));
    if (extremes.top == extremes.bottom) {
      findings.push_back(MakeFinding(Check::kFlat, sensor.slot, Severity::kInfo,
                                     "channel " + sensor.slot + " is constant (" + Number(x(0)) + " " +
                                         sensor.unit +
                                         ") over the whole record: check that it was recorded."));
      continue;
    }
    const int run_samples = config.screening.saturation_run_samples;
    if (std::optional<Finding> finding = CheckSaturation(sensor, raw_signals, x, extremes, run_samples))
      findings.push_back(std::move(*finding));
    if (std::optional<Finding> finding = CheckSpikes(sensor, raw_signals, x, config.screening))
      findings.push_back(std::move(*finding));
  }
  ThrowIfCancelled(cancel);
  if (all_finite) CheckBias(array, columns, raw_signals, initial, config, findings);
  return findings;
}

}  // namespace napkin::engine
