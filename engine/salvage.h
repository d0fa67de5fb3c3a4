#pragma once
// Salvage of a test with a faulty channel (docs/algorithms.md "Faulty
// channels"). Screening names a broken channel by an error finding: `fault`
// (its omission makes the array rigid: a dropout, a stuck or clipped
// stretch, spikes), `polarity` (sign flipped), `axis_label` (two channels
// swapped), `saturation` (a clipped top) or `non_finite` (NaN samples).
// Such a test fails unless the processing config's screening.salvage asks
// for one of:
//   exclude  solve with the array less the faulty channel(s), when the
//            remaining sensors still determine the motion (the rank of the
//            remaining rigid-body equations, rate sensors included);
//   repair   keep every good sample: a flipped channel is inverted, a
//            swapped pair swapped back, and the faulty samples of any other
//            fault (with a margin) replaced by the channel's rigid-body
//            prediction from the other channels; the whole array is solved.
// The pipeline (engine/pipeline.cpp) runs these; this file holds the
// numerics: which findings name a salvageable channel, the reduced array,
// the prediction of a channel from the others and the samples to replace.
#include <optional>
#include <string>
#include <vector>

#include "engine/array_geometry.h"
#include "engine/processing.h"
#include "engine/signals.h"
#include "engine/summary.h"

namespace napkin::engine {

// At most this many channels are excluded or repaired in one test: beyond
// two, a test is no longer a recording with a broken channel.
inline constexpr int kMaxSalvagedChannels = 2;

// A channel an error finding names as broken, and how it was found.
struct FaultyChannel {
  std::string channel;
  Check check = Check::kFault;         // kFault, kPolarity, kAxisLabel, kSaturation or kNonFinite
  std::optional<std::string> partner;  // the other channel of a swap, or of a confounded pair
};

// The faulty channels the error findings name (each once), in finding order.
std::vector<FaultyChannel> SalvageableFaults(const std::vector<Finding>& findings);

// Two channels screening cannot tell apart (two `fault` findings naming
// each other, engine/screening.cpp "confounded") are decided by their
// recorded samples when only one of them shows a fault a recorder makes
// (zeros or NaN, a flat run, a clip, spikes): that one stays in `faults`,
// without its partner. Otherwise both stay, and salvage needs the array
// without both.
void ResolveConfounded(const ArrayGeometry& array, const TestSignals& raw_signals,
                       const InitialState& initial, const ProcessingConfig& config,
                       const std::vector<Finding>& findings, std::vector<FaultyChannel>& faults);

// Every channel `faults` name, partners included, each once.
std::vector<std::string> FaultyChannelNames(const std::vector<FaultyChannel>& faults);

// The array less `channels`, validated, when it still determines what
// `array` does (the rotation, or the CG acceleration of an
// acceleration-only array); otherwise nullopt and `why` says why in words
// ("the remaining 5 channels do not determine the head's rotation").
std::optional<ArrayGeometry> ArrayWithout(const ArrayGeometry& array,
                                          const std::vector<std::string>& channels, std::string& why);

// One faulty channel of the raw signals, judged against its rigid-body
// prediction from the channels of `reduced_array` (which lacks it).
struct FaultAnalysis {
  FaultKind kind = FaultKind::kInconsistent;
  std::vector<Eigen::Index> samples;  // the samples to replace (the fault and its margin), ascending
  Eigen::Index first = -1;            // the first and last faulty sample (no margin); -1: none found
  Eigen::Index last = -1;
  Eigen::VectorXd predicted;  // the channel's rigid-body prediction at every raw sample, its unit
};

// Predicts each of `channels` (slots of `array` absent from
// `reduced_array`) from the signals of `reduced_array`'s channels,
// conditioned as `config` says but uncropped (so each prediction has one
// value per raw sample, in the raw channel's unit with its bias), and finds the faulty samples of each:
// beyond the departure from the prediction that the channel's own noise explains, the flat runs (stuck,
// clipped, zero) that hold such a sample, and non-finite samples. Throws InputError when the reduced array
// cannot be solved.
std::vector<FaultAnalysis> AnalyseFaults(const ArrayGeometry& array, const ArrayGeometry& reduced_array,
                                         const std::vector<std::string>& channels,
                                         const TestSignals& raw_signals, const InitialState& initial,
                                         const ProcessingConfig& config);

// The fault kind screening's check already says (flipped, swapped, clipped,
// a non-finite dropout), or nullopt when the samples must tell (kFault).
std::optional<FaultKind> KindOfCheck(Check check);

}  // namespace napkin::engine
