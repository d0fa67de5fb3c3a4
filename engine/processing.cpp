#include "engine/processing.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "common/error.h"

namespace napkin::engine {

namespace {

[[noreturn]] void ThrowBadField(const std::string& key, const std::string& requirement, double value) {
  std::ostringstream message;
  message << "processing config key \"" << key << "\" must be " << requirement << " (got " << value << ").";
  throw InputError(message.str());
}

void CheckPositive(const std::string& key, double value) {
  if (!(std::isfinite(value) && value > 0.0)) ThrowBadField(key, "a positive number", value);
}

void CheckNonNegative(const std::string& key, double value) {
  if (!(std::isfinite(value) && value >= 0.0)) ThrowBadField(key, "a non-negative number", value);
}

void CheckFinite(const std::string& key, double value) {
  if (!std::isfinite(value)) ThrowBadField(key, "a finite number", value);
}

// A setting that the others make irrelevant is refused rather than silently
// ignored: a result must not look as if it honoured it.
[[noreturn]] void ThrowIgnored(const std::string& key, const std::string& reason) {
  throw InputError("processing config key \"" + key + "\" would be ignored: " + reason + ".");
}

// Sample tolerance for comparing a sample time with a configured time.
double TimeTolerance(double dt_s) { return 1e-9 * dt_s; }

}  // namespace

void ProcessingConfig::Check() const {
  if (filter.linear_cfc) CheckPositive("filter.linear_cfc", *filter.linear_cfc);
  if (filter.angular_rate_cfc) CheckPositive("filter.angular_rate_cfc", *filter.angular_rate_cfc);
  CheckNonNegative("filter.padding_s", filter.padding_s);

  CheckFinite("bias.window_s[0]", bias.window_start_s);
  CheckFinite("bias.window_s[1]", bias.window_end_s);
  if (bias.window_end_s < bias.window_start_s)
    ThrowBadField("bias.window_s[1]", "at or after bias.window_s[0]", bias.window_end_s);
  CheckNonNegative("bias.auto_min_pre_impact_s", bias.auto_min_pre_impact_s);

  CheckFinite("time.shift_s", time.shift_s);
  if (time.start_s) CheckFinite("time.start_s", *time.start_s);
  if (time.end_s) CheckFinite("time.end_s", *time.end_s);
  if (time.start_s && time.end_s && !(*time.end_s > *time.start_s))
    ThrowBadField("time.end_s", "after time.start_s", *time.end_s);

  for (int i = 0; i < 3; ++i) {
    CheckFinite("gravity.g_fixed[" + std::to_string(i) + "]", gravity.g_fixed_mps2[i]);
    CheckPositive("bric.critical_radps[" + std::to_string(i) + "]", bric.critical_radps[i]);
  }

  CheckPositive("screening.residual_limit_g", screening.residual_limit_g);
  CheckPositive("screening.spike_size_g", screening.spike_size_g);
  CheckPositive("screening.spike_size_radps", screening.spike_size_radps);
  if (screening.saturation_run_samples < 2)
    ThrowBadField("screening.saturation_run_samples", "an integer of at least 2",
                  screening.saturation_run_samples);
  CheckPositive("screening.bias_limit_g", screening.bias_limit_g);
  CheckPositive("screening.bias_limit_radps", screening.bias_limit_radps);
  CheckPositive("plausibility.max_acceleration_g", plausibility.max_acceleration_g);
  CheckPositive("plausibility.max_angular_velocity_radps", plausibility.max_angular_velocity_radps);
  CheckPositive("plausibility.max_residual_factor", plausibility.max_residual_factor);
  CheckPositive("plausibility.max_initial_speed_mps", plausibility.max_initial_speed_mps);

  // Combinations in which a setting would be silently ignored. Only a value
  // other than the default can tell that a setting was asked for.
  if (solver == SolverKind::kSeed && gravity.compensate)
    throw InputError(
        "processing config key \"gravity.compensate\" is not supported by the seed solver (LC_COMP has no "
        "gravity "
        "term); use solver \"exact\" or turn it off.");
  const ProcessingConfig defaults;
  if (!gravity.compensate && gravity.g_fixed_mps2 != defaults.gravity.g_fixed_mps2)
    ThrowIgnored("gravity.g_fixed", "gravity.compensate is false; turn compensation on or leave g_fixed out");
  if (bias.mode != BiasMode::kWindow && (bias.window_start_s != defaults.bias.window_start_s ||
                                         bias.window_end_s != defaults.bias.window_end_s))
    ThrowIgnored("bias.window_s", std::string("bias.mode is \"") + NameOf(bias.mode) +
                                      "\", the window is read only in mode \"window\"");
  if (bias.mode != BiasMode::kAuto && bias.auto_min_pre_impact_s != defaults.bias.auto_min_pre_impact_s)
    ThrowIgnored("bias.auto_min_pre_impact_s", std::string("bias.mode is \"") + NameOf(bias.mode) +
                                                   "\", the minimum is read only in mode \"auto\"");
  if (!filter.linear_cfc && !filter.angular_rate_cfc) {
    if (filter.variant != defaults.filter.variant)
      ThrowIgnored("filter.variant", "both filter classes are \"none\"");
    if (filter.padding_s != defaults.filter.padding_s)
      ThrowIgnored("filter.padding_s", "both filter classes are \"none\"");
  }
}

SolveOptions MakeSolveOptions(const ProcessingConfig& config, const InitialState& initial) {
  SolveOptions options;
  options.solver = config.solver;
  options.initial = initial;
  options.gravity = config.gravity;
  return options;
}

namespace {

// Index of the first sample at or after t_s (within the sample tolerance);
// signals.size() when there is none. Sample times t0 + k dt increase with k.
Eigen::Index FirstSampleAtOrAfter(const TestSignals& signals, double t_s) {
  const double earliest = t_s - TimeTolerance(signals.dt_s);
  Eigen::Index k = 0;
  while (k < signals.size() && signals.TimeAt(k) < earliest) ++k;
  return k;
}

// Index of the first sample after t_s (beyond the sample tolerance);
// signals.size() when there is none.
Eigen::Index FirstSampleAfter(const TestSignals& signals, double t_s) {
  const double latest = t_s + TimeTolerance(signals.dt_s);
  Eigen::Index k = 0;
  while (k < signals.size() && signals.TimeAt(k) <= latest) ++k;
  return k;
}

// Refuses signals conditioning cannot work on: a bad time base, a slot name
// per column, and finite samples only.
void CheckConditionable(const TestSignals& signals) {
  if (!(std::isfinite(signals.dt_s) && signals.dt_s > 0.0)) {
    std::ostringstream message;
    message << "the sampling interval " << signals.dt_s << " s is not a finite positive number.";
    throw InputError(message.str());
  }
  if (!std::isfinite(signals.t0_s)) throw InputError("the time of the first sample is not finite.");
  const Eigen::Index channels = signals.samples.cols();
  if (static_cast<std::size_t>(channels) != signals.slots.size())
    throw InputError("the signals have a different number of columns and slot names.");
  for (Eigen::Index c = 0; c < channels; ++c) {
    for (Eigen::Index k = 0; k < signals.size(); ++k) {
      if (!std::isfinite(signals.samples(k, c))) {
        std::ostringstream message;
        message << "channel " << signals.slots[static_cast<std::size_t>(c)]
                << " has a non-finite value at sample " << k << " (t = " << signals.TimeAt(k) << " s).";
        throw InputError(message.str());
      }
    }
  }
}

// The samples whose mean is each channel's bias, [first, first + count);
// count 0 when the bias is not removed.
struct BiasSamples {
  Eigen::Index first = 0;
  Eigen::Index count = 0;
};

BiasSamples FindBiasSamples(const TestSignals& signals, const BiasConfig& bias) {
  const Eigen::Index n = signals.size();
  switch (bias.mode) {
    case BiasMode::kNone:
      break;
    case BiasMode::kAuto: {
      // Samples with t < 0 (t_k = t0 + k dt); used when they cover the
      // configured minimum pre-impact duration.
      const Eigen::Index negative = FirstSampleAtOrAfter(signals, 0.0);
      if (negative > 0 &&
          static_cast<double>(negative) * signals.dt_s >= bias.auto_min_pre_impact_s * (1.0 - 1e-9))
        return {0, negative};
      break;
    }
    case BiasMode::kWindow: {
      const Eigen::Index first = FirstSampleAtOrAfter(signals, bias.window_start_s);
      const Eigen::Index last = FirstSampleAfter(signals, bias.window_end_s);  // one past
      if (last == first) {
        std::ostringstream message;
        message << "the bias window [" << bias.window_start_s << ", " << bias.window_end_s
                << "] s holds no sample of the data (which span " << signals.TimeAt(0) << " to "
                << signals.TimeAt(n - 1) << " s after the shift).";
        throw InputError(message.str());
      }
      return {first, last - first};
    }
  }
  return {};
}

// CFC filtering per sensor kind; columns of no sensor of `array` stay as they
// are, and so do columns the file records as filtered at the requested class
// or a narrower one. Records the class applied in `conditioning`.
void FilterChannels(const ArrayGeometry& array, TestSignals& signals, const FilterConfig& config,
                    std::vector<ChannelConditioning>& conditioning, const std::atomic<bool>* cancel,
                    Eigen::VectorXd* filter_work) {
  std::optional<CfcFilter> linear_filter, rate_filter;
  if (config.linear_cfc)
    linear_filter.emplace(*config.linear_cfc, signals.dt_s, config.variant, config.padding_s);
  if (config.angular_rate_cfc)
    rate_filter.emplace(*config.angular_rate_cfc, signals.dt_s, config.variant, config.padding_s);
  std::vector<Eigen::Index> linear_columns, rate_columns;
  for (Eigen::Index c = 0; c < signals.samples.cols(); ++c) {
    const std::string& slot = signals.slots[static_cast<std::size_t>(c)];
    const auto sensor = std::find_if(array.sensors.begin(), array.sensors.end(),
                                     [&](const Sensor& candidate) { return candidate.slot == slot; });
    if (sensor == array.sensors.end()) continue;
    const bool linear = sensor->kind == SensorKind::kLinear;
    std::optional<CfcFilter>& filter = linear ? linear_filter : rate_filter;
    const std::optional<double>& requested = linear ? config.linear_cfc : config.angular_rate_cfc;
    if (!filter || !requested) continue;
    ChannelConditioning& record = conditioning[static_cast<std::size_t>(c)];
    if (record.prefiltered_cfc && PrefilterCovers(*record.prefiltered_cfc, *requested)) {
      record.filter_skipped_prefiltered = true;
      continue;
    }
    (linear ? linear_columns : rate_columns).push_back(c);
    record.filter_cfc = *requested;
  }
  // Several channels at once (CfcFilter::ApplyInPlaceToColumns), in the
  // caller's buffer when it lends one (taken back after each filter).
  const auto filter_columns = [&](CfcFilter& filter, const std::vector<Eigen::Index>& columns) {
    if (filter_work != nullptr) filter.SwapWork(*filter_work);
    filter.ApplyInPlaceToColumns(signals.samples, columns, cancel);
    if (filter_work != nullptr) filter.SwapWork(*filter_work);
  };
  if (!linear_columns.empty()) filter_columns(*linear_filter, linear_columns);
  if (!rate_columns.empty()) filter_columns(*rate_filter, rate_columns);
}

// Keeps the samples within [start_s, end_s] (either end optional).
void Crop(TestSignals& signals, const TimeConfig& time) {
  if (!time.start_s && !time.end_s) return;
  const Eigen::Index n = signals.size();
  const Eigen::Index first = time.start_s ? FirstSampleAtOrAfter(signals, *time.start_s) : 0;
  // One past the last sample kept. Never before `first`: Check() puts
  // end_s after start_s.
  const Eigen::Index last = time.end_s ? FirstSampleAfter(signals, *time.end_s) : n;
  if (last - first < 2) {
    std::ostringstream message;
    message << "the time window [" << (time.start_s ? *time.start_s : signals.TimeAt(0)) << ", "
            << (time.end_s ? *time.end_s : signals.TimeAt(n - 1))
            << "] s leaves fewer than 2 samples of the data (which span " << signals.TimeAt(0) << " to "
            << signals.TimeAt(n - 1) << " s after the shift).";
    throw InputError(message.str());
  }
  const double new_t0 = signals.TimeAt(first);
  Eigen::MatrixXd cropped = signals.samples.middleRows(first, last - first);
  signals.samples = std::move(cropped);
  signals.t0_s = new_t0;
}

}  // namespace

bool PrefilterCovers(double prefiltered_cfc, double requested_cfc) {
  // A filter of unknown class covers nothing: the requested class is applied.
  return prefiltered_cfc != kPrefilteredClassUnknown && prefiltered_cfc <= requested_cfc * (1.0 + 1e-9);
}

std::vector<ChannelConditioning> ApplyConditioning(const ArrayGeometry& array, TestSignals& signals,
                                                   const ProcessingConfig& config,
                                                   const std::atomic<bool>* cancel,
                                                   Eigen::VectorXd* filter_work) {
  config.Check();
  CheckConditionable(signals);
  std::vector<ChannelConditioning> conditioning(static_cast<std::size_t>(signals.samples.cols()));
  for (Eigen::Index c = 0; c < signals.samples.cols(); ++c) {
    ChannelConditioning& record = conditioning[static_cast<std::size_t>(c)];
    record.channel = signals.slots[static_cast<std::size_t>(c)];
    record.time_shift_s = config.time.shift_s;
    record.prefiltered_cfc = signals.PrefilteredCfc(c);
  }

  // 1. Time shift (report section 3.4).
  signals.t0_s -= config.time.shift_s;

  // 2. Bias removal: the mean over the pre-impact samples.
  const BiasSamples bias = FindBiasSamples(signals, config.bias);
  if (bias.count > 0) {
    for (Eigen::Index c = 0; c < signals.samples.cols(); ++c) {
      const double mean = signals.samples.col(c).segment(bias.first, bias.count).mean();
      signals.samples.col(c).array() -= mean;
      ChannelConditioning& record = conditioning[static_cast<std::size_t>(c)];
      record.bias_removed = mean;
      record.bias_window_start_s = signals.TimeAt(bias.first);
      record.bias_window_end_s = signals.TimeAt(bias.first + bias.count - 1);
    }
  }

  // 3. CFC filtering per sensor kind.
  FilterChannels(array, signals, config.filter, conditioning, cancel, filter_work);

  // 4. Crop.
  Crop(signals, config.time);
  return conditioning;
}

std::vector<Finding> ConditioningFindings(const std::vector<ChannelConditioning>& conditioning) {
  std::vector<Finding> findings;
  for (const ChannelConditioning& record : conditioning) {
    if (!record.prefiltered_cfc) continue;
    std::ostringstream detail;
    detail << "channel " << record.channel << " is recorded in the file as filtered";
    if (*record.prefiltered_cfc == kPrefilteredClassUnknown)
      detail << ", at a class it does not name";
    else
      detail << " at CFC " << *record.prefiltered_cfc;
    if (record.filter_skipped_prefiltered)
      detail << ", so napkin did not filter it again.";
    else if (record.filter_cfc)
      detail << "; napkin filtered it at "
             << (*record.prefiltered_cfc == kPrefilteredClassUnknown ? "" : "the narrower ") << "CFC "
             << *record.filter_cfc << " as configured.";
    else
      detail << "; napkin applied no filter to it.";
    findings.push_back({"prefiltered", record.channel, Severity::kInfo, detail.str()});
  }
  return findings;
}

}  // namespace napkin::engine
