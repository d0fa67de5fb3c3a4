#pragma once
// Data screening: what the report asks the engineer to check by eye before
// solving (report section 2.2, "checked for bias error and for overall data
// quality ... spurious spikes, saturation ... polarity errors"; section 3.4,
// "the three accelerations along each body axis were plotted as a group").
// Every finding names its check, the slot at fault (or none for the whole
// test), a severity and one sentence of detail.
//
// Checks and severities:
//   missing      error    an array slot has no column in the signals
//   non_finite   error    NaN or infinite samples (a dropout)
//   saturation   error    a run of >= saturation_run_samples equal samples at
//                         the channel's extreme (a clipped, flat-topped pulse)
//   spike        warning  one-sample jumps against both neighbours
//   bias         warning  a zero offset: the pre-impact mean (t < 0 after the
//                         shift) beyond bias_limit_*; without pre-impact data,
//                         a channel starting beyond the limit while the others
//                         start near zero, or (rigid-body check) a channel
//                         whose discrepancy from what the other channels
//                         imply is a near-constant offset beyond the limit
//   flat         info     the channel never changes (dead or unrecorded)
//   polarity     error    flipping one channel's sign makes the array rigid
//   axis_label   error    swapping two channels makes the array rigid
//   residual     warning  the exact solver's rigid-body residual exceeds
//                         residual_limit_g (a channel inconsistent with a
//                         rigid body), with the channel whose omission
//                         removes most of it
//   fault        error    a channel (or a pair) whose omission makes the
//                         array rigid: its departure from what the others
//                         imply, or the residual's 10-fold fall without it
//                         (docs/algorithms.md "Faulty channels"); salvage
//                         (engine/salvage.h) excludes or repairs it
//   consistency  info     the array has no redundant channel, so polarity,
//                         labels and the residual cannot be checked
//   implausible  error    a raw channel, the solved CG acceleration or angular
//                         velocity, or the rigid-body residual beyond the
//                         processing config's plausibility limits (a corrupt
//                         sample or a wrong unit, not a real impact)
//
// ProcessTest (engine/pipeline.h) runs ScreenSignals on the raw signals
// first; a `missing` or `non_finite` finding stops processing with an
// InputError carrying the finding's sentence (naming slot, sample and time).
// Every other finding is reported in the summary and processing continues:
// a flipped or swapped channel, saturation or a spike still yields numbers,
// but the error/warning findings flag them as untrustworthy. The one
// exception: when the channels are so far from a rigid body that the
// integrated angular velocity of a linear-only array diverges, there are no
// numbers to flag, and ProcessTest stops with an InputError that quotes the
// screening finding (e.g. the flipped channel).
//
// Limitation: the polarity of an angular-rate channel is judged through
// the fused solver's residual, which weights the differentiated rates
// lightly; a flipped rate sensor is caught only when it drives that
// residual over residual_limit_g.
#include <atomic>
#include <vector>

#include "engine/array_geometry.h"
#include "engine/kinematics.h"
#include "engine/processing.h"
#include "engine/signals.h"
#include "engine/solver.h"
#include "engine/summary.h"

namespace napkin::engine {

// Checks on the raw (unconditioned) signals of the array's slots: missing,
// non_finite, flat, saturation, spike, bias. `config` supplies the
// screening thresholds, the time shift (pre-impact means t < 0 after the
// shift) and the bias mode (to say whether the offset will be removed).
// Never throws on bad data: every problem becomes a finding. Looks at
// `cancel` (engine/cancellation.h) between channels: throws Cancelled when set.
std::vector<Finding> ScreenSignals(const ArrayGeometry& array, const TestSignals& raw_signals,
                                   const InitialState& initial, const ProcessingConfig& config,
                                   const std::atomic<bool>* cancel = nullptr);

// Rigid-body consistency of the conditioned signals, given the exact
// solver's kinematics for them (`exact_options` as used for that solve):
// residual, polarity, axis_label, bias, consistency. Only when the residual
// peaks above residual_limit_g (or its median exceeds half the bias limit)
// does it re-solve the test under each hypothesis (one channel's sign
// flipped, two channels of one kind swapped, one channel left out), so clean
// tests cost nothing extra. A flip or swap is reported when it lowers the
// RMS residual below a quarter of the recorded one and below the limit.
std::vector<Finding> ScreenConsistency(const ArrayGeometry& array, const TestSignals& conditioned_signals,
                                       const Kinematics& exact_kinematics, const SolveOptions& exact_options,
                                       const ScreeningConfig& config);

// Physical plausibility of the solved motion (ProcessingConfig::plausibility):
// the peak |CG acceleration|, |angular velocity| and the exact solver's
// rigid-body residual (m/s^2) beyond max_residual_factor x residual_limit_g;
// one `implausible` error finding each, naming the quantity, sample, time
// and value. The kinematics must be finite.
std::vector<Finding> ScreenPlausibility(const Kinematics& kinematics, const Eigen::VectorXd& exact_residual,
                                        const ProcessingConfig& config);

// A threshold given in g (linear sensors) or rad/s (angular-rate sensors),
// in `sensor`'s unit.
double InChannelUnits(const Sensor& sensor, double limit_g, double limit_radps);

// The median (the upper one of an even count) of `values`, which it reorders.
double MedianInPlace(std::vector<double>& values);

// What `sensor` should read at sample `k` of rigid-body kinematics solved
// without it (report section 2.1: n . (a + alpha x r + omega x (omega x r))
// for a linear sensor, n . omega for an angular-rate sensor), in the
// sensor's unit; gravity is not added (the kinematics of a trial solve
// carry the sensed acceleration, gravity included).
double PredictedReading(const Sensor& sensor, const Kinematics& kinematics, Eigen::Index k);

// True for the findings after which the data cannot be processed at all
// (missing or non-finite samples).
bool IsFatal(const Finding& finding);

// Appends `more` to `findings`, skipping a check already reported for the
// same channel (e.g. a bias seen both in the raw signals and by the rigid
// body).
void AppendFindings(const std::vector<Finding>& more, std::vector<Finding>& findings);

// Number of redundant rigid-body equations the exact solver's residual
// measures for `array` (0: no consistency check is possible). Throws
// InvalidArrayError when the array cannot be solved.
int ResidualRedundancy(const ArrayGeometry& array);

}  // namespace napkin::engine
