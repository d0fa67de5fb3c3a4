#include "engine/salvage.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "common/error.h"
#include "engine/screening.h"
#include "engine/solver.h"
#include "engine/units.h"

namespace napkin::engine {
namespace {

using Eigen::Index;

// A sample is faulty when it departs from the channel's rigid-body prediction
// by more than kRepairSigmas robust standard deviations of that departure
// (1.4826 x its median absolute value: the channel's own noise plus the
// prediction's, measured on the record's good samples, which are most of
// it), and by at least kRepairFloorFraction x residual_limit_g (exact data
// have no noise to measure).
constexpr double kRepairSigmas = 6.0;
constexpr double kRepairFloorFraction = 0.05;
// The margin replaced on each side of a fault: a recorder's fault edge can
// smear over a sample or two (kMarginS, at least kMarginMinSamples).
constexpr double kMarginS = 0.0002;
constexpr Index kMarginMinSamples = 2;
// Runs of equal samples this long are what a stuck, clipped or dropped-out
// ADC returns: a run holding a faulty sample is faulty as a whole.
constexpr Index kFlatRunMinSamples = 3;
// A fault segment of at most this many samples is a spike.
constexpr Index kSpikeMaxSamples = 3;

// A flat run is a clip when the prediction lies beyond it (same sign,
// larger magnitude) over most of it, stuck otherwise.
FaultKind KindOfSamples(const Eigen::Ref<const Eigen::VectorXd>& recorded, const Eigen::VectorXd& predicted,
                        const std::vector<bool>& faulty, const std::vector<bool>& in_flat_run, Index segments,
                        Index longest_segment) {
  Index count = 0, non_finite = 0, zero = 0, flat = 0, beyond = 0;
  for (Index k = 0; k < recorded.size(); ++k) {
    if (!faulty[static_cast<std::size_t>(k)]) continue;
    ++count;
    if (!std::isfinite(recorded(k))) {
      ++non_finite;
      continue;
    }
    if (recorded(k) == 0.0) ++zero;
    if (in_flat_run[static_cast<std::size_t>(k)]) {
      ++flat;
      if (predicted(k) * recorded(k) > 0.0 && std::abs(predicted(k)) > std::abs(recorded(k))) ++beyond;
    }
  }
  if (count == 0) return FaultKind::kInconsistent;
  if (non_finite > 0 || 2 * zero >= count) return FaultKind::kDropout;
  if (2 * flat >= count) return 10 * beyond >= 9 * flat ? FaultKind::kClipped : FaultKind::kStuck;
  if (segments > 0 && longest_segment <= kSpikeMaxSamples) return FaultKind::kSpike;
  return FaultKind::kInconsistent;
}

}  // namespace

std::vector<FaultyChannel> SalvageableFaults(const std::vector<Finding>& findings) {
  std::vector<FaultyChannel> faults;
  std::set<std::string> named;
  for (const Finding& finding : findings) {
    if (finding.severity != Severity::kError || !finding.channel) continue;
    const std::optional<Check> check = ParseName<Check>(finding.check);
    if (!check || !(*check == Check::kFault || KindOfCheck(*check).has_value())) continue;
    if (named.count(*finding.channel) != 0) continue;
    FaultyChannel fault{*finding.channel, *check, std::nullopt};
    if (*check == Check::kAxisLabel || *check == Check::kFault) {
      // A swap's two findings name each other ("channels A and B appear
      // swapped"), and so do a confounded pair's ("... cannot be told apart").
      for (const Finding& other : findings)
        if (other.check == finding.check && other.channel && *other.channel != *finding.channel &&
            other.detail == finding.detail)
          fault.partner = other.channel;
      if (fault.partner) named.insert(*fault.partner);
    }
    named.insert(fault.channel);
    faults.push_back(std::move(fault));
  }
  return faults;
}

void ResolveConfounded(const ArrayGeometry& array, const TestSignals& raw_signals,
                       const InitialState& initial, const ProcessingConfig& config,
                       const std::vector<Finding>& findings, std::vector<FaultyChannel>& faults) {
  // A fault a recorder makes, seen in the channel's own samples: zeros, a
  // flat run, a clip, or a raw-signal finding (spike, saturation, NaN).
  const auto shows_fault = [&](const std::string& channel) {
    for (const Finding& finding : findings)
      if (finding.channel == channel &&
          (finding.check == NameOf(Check::kSpike) || finding.check == NameOf(Check::kSaturation) ||
           finding.check == NameOf(Check::kNonFinite)))
        return true;
    std::string why;
    const std::optional<ArrayGeometry> reduced = ArrayWithout(array, {channel}, why);
    if (!reduced) return false;
    const FaultKind kind =
        AnalyseFaults(array, *reduced, {channel}, raw_signals, initial, config).front().kind;
    return kind == FaultKind::kDropout || kind == FaultKind::kStuck || kind == FaultKind::kClipped;
  };
  for (FaultyChannel& fault : faults) {
    if (fault.check != Check::kFault || !fault.partner) continue;
    const bool first = shows_fault(fault.channel), second = shows_fault(*fault.partner);
    if (first == second) continue;  // the samples do not tell either
    if (second) fault.channel = *fault.partner;
    fault.partner.reset();
  }
}

std::vector<std::string> FaultyChannelNames(const std::vector<FaultyChannel>& faults) {
  std::vector<std::string> names;
  const auto add = [&names](const std::string& name) {
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  };
  for (const FaultyChannel& fault : faults) {
    add(fault.channel);
    if (fault.partner) add(*fault.partner);
  }
  return names;
}

std::optional<FaultKind> KindOfCheck(Check check) {
  switch (check) {
    case Check::kPolarity:
      return FaultKind::kFlipped;
    case Check::kAxisLabel:
      return FaultKind::kSwapped;
    case Check::kSaturation:
      return FaultKind::kClipped;
    case Check::kNonFinite:
      return FaultKind::kDropout;
    default:
      return std::nullopt;
  }
}

std::optional<ArrayGeometry> ArrayWithout(const ArrayGeometry& array,
                                          const std::vector<std::string>& channels, std::string& why) {
  ArrayGeometry validated = array;
  ValidateArray(validated);
  const bool rotation = DeterminesRotation(validated);
  ArrayGeometry reduced = validated;
  reduced.sensors.erase(std::remove_if(reduced.sensors.begin(), reduced.sensors.end(),
                                       [&channels](const Sensor& sensor) {
                                         return std::find(channels.begin(), channels.end(), sensor.slot) !=
                                                channels.end();
                                       }),
                        reduced.sensors.end());
  const std::string remaining = "the remaining " + std::to_string(reduced.sensors.size()) + " of " +
                                std::to_string(array.sensors.size()) + " channels";
  try {
    ValidateArray(reduced);
  } catch (const InputError&) {
    why = remaining + " do not determine the motion";
    return std::nullopt;
  }
  if (rotation && !DeterminesRotation(reduced)) {
    why = remaining + " do not determine the head's rotation";
    return std::nullopt;
  }
  return reduced;
}

std::vector<FaultAnalysis> AnalyseFaults(const ArrayGeometry& array, const ArrayGeometry& reduced_array,
                                         const std::vector<std::string>& channels,
                                         const TestSignals& raw_signals, const InitialState& initial,
                                         const ProcessingConfig& config) {
  // The signals: shifted and bias-corrected as the config says but not
  // cropped (a prediction per raw sample). The departures are judged on the
  // unfiltered samples, where a fault's edges are sharp; the prediction
  // comes from the filtered ones, so that the replaced samples carry no
  // more noise than the channel's own (conditioning filters them again with
  // the rest: a smooth prediction passes a CFC filter unchanged). The
  // faulty channels' non-finite samples are zeroed: they are replaced
  // anyway, and no other channel depends on them.
  TestSignals work = raw_signals;
  for (const std::string& channel : channels) {
    const int column = work.FindSlot(channel);
    if (column < 0) throw InputError("the signals have no channel for slot " + channel + ".");
    auto samples = work.samples.col(column);
    for (Index k = 0; k < samples.size(); ++k)
      if (!std::isfinite(samples(k))) samples(k) = 0.0;
  }
  ProcessingConfig uncropped = config;
  uncropped.time.start_s.reset();
  uncropped.time.end_s.reset();
  TestSignals smooth = work;
  ProcessingConfig unfiltered = uncropped;
  unfiltered.filter.linear_cfc.reset();
  unfiltered.filter.angular_rate_cfc.reset();
  const std::vector<ChannelConditioning> conditioning = ApplyConditioning(array, work, unfiltered);
  ApplyConditioning(array, smooth, uncropped);
  SolveOptions options = MakeSolveOptions(uncropped, initial);
  options.solver = SolverKind::kExact;
  options.gravity.compensate = false;
  options.body_frame_only = true;
  const Kinematics kinematics = Solve(reduced_array, smooth, options);

  std::vector<FaultAnalysis> analyses;
  const Index n = raw_signals.size();
  const Index margin = std::max<Index>(kMarginMinSamples, std::llround(kMarginS / raw_signals.dt_s));
  for (const std::string& channel : channels) {
    const std::optional<std::size_t> index = array.FindSlot(channel);
    if (!index) throw InputError("array " + array.name + " has no slot " + channel + ".");
    const Sensor& sensor = array.sensors[*index];
    const int column = work.FindSlot(channel);
    const auto recorded = raw_signals.samples.col(column);
    FaultAnalysis analysis;
    analysis.predicted.resize(n);
    const double bias = conditioning[static_cast<std::size_t>(column)].bias_removed;
    std::vector<double> departure(static_cast<std::size_t>(n));
    for (Index k = 0; k < n; ++k) {
      const double predicted = PredictedReading(sensor, kinematics, k);
      analysis.predicted(k) = predicted + bias;
      departure[static_cast<std::size_t>(k)] = work.samples(k, column) - predicted;
    }
    std::vector<double> magnitude(departure.size());
    std::transform(departure.begin(), departure.end(), magnitude.begin(),
                   [](double d) { return std::abs(d); });
    std::vector<double> scratch = magnitude;
    const double sigma = 1.4826 * MedianInPlace(scratch);
    const double threshold =
        std::max(kRepairSigmas * sigma,
                 InChannelUnits(sensor, kRepairFloorFraction * config.screening.residual_limit_g,
                                config.screening.bias_limit_radps));
    std::vector<bool> faulty(static_cast<std::size_t>(n), false);
    for (Index k = 0; k < n; ++k)
      faulty[static_cast<std::size_t>(k)] =
          !std::isfinite(recorded(k)) || magnitude[static_cast<std::size_t>(k)] > threshold;
    // A run of equal recorded samples (a stuck ADC code) holding a faulty
    // sample is faulty throughout: near the fault's edges it may still lie
    // within the noise of the truth, but it is no measurement.
    std::vector<bool> in_flat_run(static_cast<std::size_t>(n), false);
    for (Index start = 0; start < n;) {
      Index end = start + 1;
      while (end < n && recorded(end) == recorded(start)) ++end;
      if (end - start >= kFlatRunMinSamples) {
        bool holds_fault = false;
        for (Index k = start; k < end; ++k) holds_fault = holds_fault || faulty[static_cast<std::size_t>(k)];
        for (Index k = start; k < end; ++k) {
          in_flat_run[static_cast<std::size_t>(k)] = true;
          if (holds_fault) faulty[static_cast<std::size_t>(k)] = true;
        }
      }
      start = end;
    }
    Index segments = 0, longest = 0, run = 0;
    for (Index k = 0; k <= n; ++k) {
      if (k < n && faulty[static_cast<std::size_t>(k)]) {
        if (analysis.first < 0) analysis.first = k;
        analysis.last = k;
        ++run;
        continue;
      }
      if (run > 0) {
        ++segments;
        longest = std::max(longest, run);
      }
      run = 0;
    }
    analysis.kind = KindOfSamples(recorded, analysis.predicted, faulty, in_flat_run, segments, longest);
    // The faulty samples and their margins.
    std::vector<bool> replace(static_cast<std::size_t>(n), false);
    for (Index k = 0; k < n; ++k) {
      if (!faulty[static_cast<std::size_t>(k)]) continue;
      for (Index j = std::max<Index>(0, k - margin); j <= std::min<Index>(n - 1, k + margin); ++j)
        replace[static_cast<std::size_t>(j)] = true;
    }
    for (Index k = 0; k < n; ++k)
      if (replace[static_cast<std::size_t>(k)]) analysis.samples.push_back(k);
    analyses.push_back(std::move(analysis));
  }
  return analyses;
}

}  // namespace napkin::engine
