// The rigid-body consistency checks of screening (engine/screening.h): the
// residual, polarity, axis labels, faulty channels; the per-channel checks
// of the raw signals are engine/channel_checks.cpp.
#include "engine/screening.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>
#include <string>

#include "common/error.h"
#include "engine/exact_solver.h"
#include "engine/screening_text.h"
#include "engine/units.h"

namespace napkin::engine {

double InChannelUnits(const Sensor& sensor, double limit_g, double limit_radps) {
  const double limit_si = sensor.kind == SensorKind::kLinear ? limit_g * kStandardGravity : limit_radps;
  return limit_si / sensor.si_per_unit;
}

double MedianInPlace(std::vector<double>& values) {
  if (values.empty()) return 0.0;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

namespace {

using Eigen::Index;
using internal::FromTo;
using internal::MakeFinding;
using internal::Median;
using internal::Number;
using internal::Rms;

// A hypothesis (flip, swap) "fits much better" when it lowers the RMS
// rigid-body residual below this fraction of the recorded one; leaving out
// one channel names it as the culprit below kLeaveOutFraction.
constexpr double kHypothesisFraction = 0.25;
constexpr double kLeaveOutFraction = 0.5;
// A channel is faulty (an error finding, docs/algorithms.md "Faulty
// channels") when, solved without it, the other channels imply a reading it
// departs from by more than residual_limit_g and by more than kFaultSigmas
// robust standard deviations of that departure (the channel's own noise and
// the prediction's: a broken channel departs by its fault, a noisy one by
// its noise, 8 sigma being beyond any sample of a Gaussian record of 10^7
// samples), or when leaving it out lowers the RMS rigid-body residual at
// least kFaultImprovement-fold while the residual peaks above
// kFaultPeakFraction x residual_limit_g (noise on every channel leaves a
// residual no single omission removes: a 1.1- to 1.5-fold improvement at
// 0.5 g RMS per channel). The departure judges a fault the least squares
// hides in alpha (a channel of high leverage leaves little residual).
constexpr double kFaultImprovement = 10.0;
constexpr double kFaultPeakFraction = 0.5;
constexpr double kFaultSigmas = 8.0;
// The fault's interval: where the departure exceeds kFaultSigmas robust
// standard deviations and kFaultFloorFraction x residual_limit_g.
constexpr double kFaultFloorFraction = 0.1;
// ... and never below kFaultFloorMinG: a residual limit set low to see the
// round-off of exact data (1e-4 g) must not make that round-off a fault
// (a departure of 0.05 g on one channel moves no criterion by 0.1 %).
constexpr double kFaultFloorMinG = 0.05;

double LinearFaultFloorG(const ScreeningConfig& config) {
  return std::max(kFaultFloorFraction * config.residual_limit_g, kFaultFloorMinG);
}
// A discrepancy counts as a constant offset when its RMS deviation from its
// median is below this fraction of the median.
constexpr double kOffsetSpreadFraction = 0.5;

// --- consistency checks ----------------------------------------------------

struct ResidualFit {
  double rms = 0.0;
  bool solved = false;
};

// The RMS residual of a trial solve into `kinematics` (kept from trial to
// trial: the trials map no new pages).
ResidualFit SolveResidual(const ArrayGeometry& array, const TestSignals& signals, const SolveOptions& options,
                          Kinematics& kinematics) {
  ResidualFit fit;
  try {
    Solve(array, signals, options, kinematics);
    fit.rms = Rms(kinematics.residual);
    fit.solved = std::isfinite(fit.rms);
  } catch (const InputError&) {
    fit.solved = false;  // e.g. the array without one channel is not solvable
  }
  return fit;
}

// A channel whose discrepancy from what the other channels imply is nearly
// constant carries a zero offset (report section 2.2, "bias error"): found
// this way even when the record has no pre-impact data and the head is
// already moving at its start. Gravity compensation is off in the solves
// here, so zeroed channels should match exactly.
std::optional<Finding> ExplainAsOffset(const Sensor& sensor, const TestSignals& signals,
                                       const Kinematics& kinematics_without, const ScreeningConfig& config) {
  const int column = signals.FindSlot(sensor.slot);
  if (column < 0 || kinematics_without.size() != signals.size()) return std::nullopt;
  const Index n = signals.size();
  Eigen::VectorXd discrepancy(n);
  for (Index k = 0; k < n; ++k)
    discrepancy(k) = signals.samples(k, column) - PredictedReading(sensor, kinematics_without, k);
  if (!discrepancy.allFinite()) return std::nullopt;
  const double offset = Median(std::vector<double>(discrepancy.data(), discrepancy.data() + n));
  const double limit = InChannelUnits(sensor, config.bias_limit_g, config.bias_limit_radps);
  const double spread = Rms((discrepancy.array() - offset).matrix());
  if (!(std::abs(offset) > limit && spread < kOffsetSpreadFraction * std::abs(offset))) return std::nullopt;
  std::ostringstream detail;
  detail << "channel " << sensor.slot << " reads a nearly constant " << Number(offset) << " " << sensor.unit
         << " (RMS deviation " << Number(spread, 2) << " " << sensor.unit
         << ") off what the other channels imply for a rigid body: a zero offset beyond the " << Number(limit)
         << " " << sensor.unit << " bias limit.";
  return MakeFinding(Check::kBias, sensor.slot, Severity::kWarning, detail.str());
}

// What the exact solver's rigid-body residual says at a glance.
struct ResidualStatistics {
  double peak_mps2 = 0.0;  // +infinity when the solve diverged
  Index peak_at = 0;       // sample of the peak, or where the solve diverges
  double median_mps2 = 0.0;
  double rms_mps2 = 0.0;  // +infinity when the solve diverged
};

ResidualStatistics StatisticsOf(const Kinematics& kinematics) {
  ResidualStatistics statistics;
  // Peak residual; a diverged solve (non-finite) peaks where it diverges.
  for (Index k = 0; k < kinematics.size(); ++k) {
    const double value = kinematics.residual(k);
    if (!std::isfinite(value) || !std::isfinite(kinematics.omega_body.row(k).squaredNorm())) {
      statistics.peak_mps2 = std::numeric_limits<double>::infinity();
      statistics.peak_at = k;
      break;
    }
    if (value > statistics.peak_mps2) {
      statistics.peak_mps2 = value;
      statistics.peak_at = k;
    }
  }
  statistics.median_mps2 =
      Median(std::vector<double>(kinematics.residual.data(), kinematics.residual.data() + kinematics.size()));
  statistics.rms_mps2 = Rms(kinematics.residual);
  return statistics;
}

// The solver options of the trial solves: exact, without gravity
// compensation (the residual ignores it; predicted readings must not include
// it), and the body-frame series only (all the trials read).
SolveOptions TrialOptions(const SolveOptions& exact_options) {
  SolveOptions options = exact_options;
  options.solver = SolverKind::kExact;
  options.gravity.compensate = false;
  options.body_frame_only = true;
  return options;
}

Finding FlipFinding(const Sensor& sensor, double recorded_rms, double flipped_rms) {
  return MakeFinding(Check::kPolarity, sensor.slot, Severity::kError,
                     "channel " + sensor.slot +
                         " appears sign flipped: flipping it lowers the RMS rigid-body residual " +
                         FromTo(recorded_rms, flipped_rms) + ".");
}

Finding SwapFinding(const Sensor& sensor, const Sensor& other, double recorded_rms, double swapped_rms) {
  return MakeFinding(Check::kAxisLabel, sensor.slot, Severity::kError,
                     "channels " + sensor.slot + " and " + other.slot +
                         " appear swapped: swapping them lowers the RMS rigid-body residual " +
                         FromTo(recorded_rms, swapped_rms) + ".");
}

// The residual with the channel in `column` of `trial` sign flipped; `trial`
// is returned to `signals` afterwards.
ResidualFit SolveFlipped(const ArrayGeometry& array, const TestSignals& signals, TestSignals& trial,
                         int column, const SolveOptions& options, Kinematics& kinematics) {
  trial.samples.col(column) *= -1.0;
  ResidualFit fit = SolveResidual(array, trial, options, kinematics);
  trial.samples.col(column) = signals.samples.col(column);
  return fit;
}

// The residual with two channels of one kind swapped; `trial` is returned to
// `signals` afterwards.
ResidualFit SolveSwapped(const ArrayGeometry& array, const TestSignals& signals, TestSignals& trial,
                         const Sensor& sensor, int column, const Sensor& other, int other_column,
                         const SolveOptions& options, Kinematics& kinematics) {
  // Channels of one kind in different units swap with the unit scale.
  const double scale = other.si_per_unit / sensor.si_per_unit;
  trial.samples.col(column) = signals.samples.col(other_column) * scale;
  trial.samples.col(other_column) = signals.samples.col(column) / scale;
  ResidualFit fit = SolveResidual(array, trial, options, kinematics);
  trial.samples.col(column) = signals.samples.col(column);
  trial.samples.col(other_column) = signals.samples.col(other_column);
  return fit;
}

// The sign flip or swap of labels under which the array is most nearly a
// rigid body (no finding when none lowers the recorded residual).
struct Hypothesis {
  double rms_mps2 = 0.0;
  std::optional<Finding> finding;
  std::optional<std::string> partner;  // the other channel of a swap
};

Hypothesis BestHypothesis(const ArrayGeometry& array, const TestSignals& signals, const SolveOptions& options,
                          double recorded_rms) {
  Hypothesis best;
  best.rms_mps2 = recorded_rms;
  TestSignals trial = signals;
  Kinematics kinematics;
  for (std::size_t i = 0; i < array.sensors.size(); ++i) {
    const Sensor& sensor = array.sensors[i];
    const int column = signals.FindSlot(sensor.slot);
    if (column < 0) continue;
    const ResidualFit fit = SolveFlipped(array, signals, trial, column, options, kinematics);
    if (fit.solved && fit.rms < best.rms_mps2)
      best = {fit.rms, FlipFinding(sensor, recorded_rms, fit.rms), {}};
    for (std::size_t j = i + 1; j < array.sensors.size(); ++j) {
      const Sensor& other = array.sensors[j];
      const int other_column = signals.FindSlot(other.slot);
      if (other_column < 0 || other.kind != sensor.kind) continue;
      const ResidualFit swap_fit =
          SolveSwapped(array, signals, trial, sensor, column, other, other_column, options, kinematics);
      if (swap_fit.solved && swap_fit.rms < best.rms_mps2)
        best = {swap_fit.rms, SwapFinding(sensor, other, recorded_rms, swap_fit.rms), other.slot};
    }
  }
  return best;
}

// The channel whose omission removes most of the residual, when that
// accounts for it.
struct Culprit {
  const Sensor* sensor = nullptr;
  double rms_mps2 = 0.0;  // RMS residual without it
  Kinematics kinematics;  // solved without it
  bool accounts = false;  // its omission removes most of the residual (kLeaveOutFraction)
  // The runner-up: the channel whose omission fits next best, with its solve.
  const Sensor* runner_up = nullptr;
  double runner_up_rms_mps2 = 0.0;
  Kinematics runner_up_kinematics;
};

// The pair of channels whose omission removes the residual, when no single
// channel does (two broken channels): searched only when the array keeps a
// redundant equation without any two of its channels.
struct CulpritPair {
  const Sensor* first = nullptr;
  const Sensor* second = nullptr;
  double rms_mps2 = 0.0;
  Kinematics kinematics;
};

// The array less the sensors at `indices`, when it keeps a redundant
// rigid-body equation to judge a trial solve by; nullopt otherwise.
std::optional<ArrayGeometry> CheckableWithout(const ArrayGeometry& array,
                                              std::initializer_list<std::size_t> indices) {
  ArrayGeometry reduced;
  reduced.name = array.name;
  for (std::size_t i = 0; i < array.sensors.size(); ++i)
    if (std::find(indices.begin(), indices.end(), i) == indices.end())
      reduced.sensors.push_back(array.sensors[i]);
  try {
    if (ResidualRedundancy(reduced) > 0) return reduced;
  } catch (const InputError&) {
  }
  return std::nullopt;
}

std::optional<CulpritPair> LeaveTwoOut(const ArrayGeometry& array, const TestSignals& signals,
                                       const SolveOptions& options, double recorded_rms) {
  CulpritPair best;
  best.rms_mps2 = recorded_rms;
  Kinematics kinematics;
  for (std::size_t i = 0; i < array.sensors.size(); ++i) {
    for (std::size_t j = i + 1; j < array.sensors.size(); ++j) {
      const std::optional<ArrayGeometry> reduced = CheckableWithout(array, {i, j});
      if (!reduced) continue;
      const ResidualFit fit = SolveResidual(*reduced, signals, options, kinematics);
      if (fit.solved && fit.rms < best.rms_mps2) {
        best.rms_mps2 = fit.rms;
        best.first = &array.sensors[i];
        best.second = &array.sensors[j];
        std::swap(best.kinematics, kinematics);
      }
    }
  }
  if (best.first == nullptr) return std::nullopt;
  return best;
}

// The leverages h_jj of the linear sensors in the exact solver's least
// squares for (a, alpha) (ExactPath::kLinear, and kFused's linear rows: row j is n_j^T [I, -[r_j]x],
// i.e. (n_j, r_j x n_j); H = A (A^T A)^-1 A^T), with the arms scaled to the
// RMS lever arm so the rows are balanced; empty when the array takes
// another path.
// The hat matrix H = A (A^T A)^-1 A^T of the linear sensors' rows, indexed
// by sensor (a rate sensor's row and column are zero: it has no linear row);
// empty when the array takes neither path.
Eigen::MatrixXd LinearHat(const ArrayGeometry& array) {
  ArrayGeometry validated = array;
  ValidateArray(validated);
  const ExactPath path = ClassifyArray(validated);
  if (path != ExactPath::kLinear && path != ExactPath::kFused) return {};
  const std::vector<std::size_t> linear = validated.LinearIndices();
  const auto n = static_cast<Index>(linear.size());
  Eigen::MatrixXd rows(n, 6);
  for (Index j = 0; j < n; ++j) {
    const Sensor& sensor = validated.sensors[linear[static_cast<std::size_t>(j)]];
    rows.block<1, 3>(j, 0) = sensor.axis_body.transpose();
    rows.block<1, 3>(j, 3) = sensor.position_body_m.cross(sensor.axis_body).transpose();
  }
  const Eigen::MatrixXd gram = rows.transpose() * rows;
  const Eigen::MatrixXd hat = rows * gram.completeOrthogonalDecomposition().solve(rows.transpose());
  const auto sensors = static_cast<Index>(validated.sensors.size());
  Eigen::MatrixXd by_sensor = Eigen::MatrixXd::Zero(sensors, sensors);
  for (Index a = 0; a < n; ++a)
    for (Index b = 0; b < n; ++b)
      by_sensor(static_cast<Index>(linear[static_cast<std::size_t>(a)]),
                static_cast<Index>(linear[static_cast<std::size_t>(b)])) = hat(a, b);
  return by_sensor;
}

std::vector<double> LinearLeverages(const ArrayGeometry& array) {
  const Eigen::MatrixXd hat = LinearHat(array);
  if (hat.size() == 0) return {};
  // Rate sensors have no linear row: leverage 1 leaves them to the rate check.
  std::vector<double> leverages(array.sensors.size(), 1.0);
  for (std::size_t j = 0; j < array.sensors.size(); ++j)
    if (array.sensors[j].kind == SensorKind::kLinear)
      leverages[j] = hat(static_cast<Index>(j), static_cast<Index>(j));
  return leverages;
}

// Whether two linear sensors' errors leave the same trace in the residual:
// their columns of I - H are parallel, so no redundant equation can tell
// which of them is off (the ideal 3-2-2-2's xarm_y and yarm_x share the one
// equation that checks alpha_z). nullopt when one is a rate sensor.
std::optional<bool> ParallelInResidual(const ArrayGeometry& array, const Sensor& first,
                                       const Sensor& second) {
  if (first.kind != SensorKind::kLinear || second.kind != SensorKind::kLinear) return std::nullopt;
  const Eigen::MatrixXd hat = LinearHat(array);
  const std::optional<std::size_t> a = array.FindSlot(first.slot), b = array.FindSlot(second.slot);
  if (hat.size() == 0 || !a || !b) return std::nullopt;
  const auto i = static_cast<Index>(*a), j = static_cast<Index>(*b);
  const double free_i = 1.0 - hat(i, i), free_j = 1.0 - hat(j, j);
  if (!(free_i > 1e-9 && free_j > 1e-9)) return false;
  return std::abs(hat(i, j)) / std::sqrt(free_i * free_j) > 1.0 - 1e-6;
}

// Trial solves of the low-residual search (LinearSuspects).
constexpr std::size_t kLinearSuspectTrials = 3;

// The channels most likely broken in a linear-path solve whose residual
// stays low (a fault the least squares hides in alpha), without a trial
// solve per channel: each channel's residual against the solved kinematics,
// r_j, divided by 1 - h_jj, is what leaving it out of the per-sample least
// squares would leave it departing by (the deleted residual of the
// linearised problem, omega held). The channel whose deleted residual
// stands farthest above kFaultSigmas robust standard deviations and
// residual_limit_g is the suspect; -1 when none does.
std::vector<std::size_t> LinearSuspects(const ArrayGeometry& array, const TestSignals& signals,
                                        const Kinematics& kinematics, const ScreeningConfig& config) {
  const std::vector<double> leverages = LinearLeverages(array);
  if (leverages.empty()) return {};
  // A channel's residual is at most the residual norm (both in m/s^2), so no
  // deleted residual can reach the floor when the norm's peak over the
  // smallest 1 - h_jj stays below it: a clean test costs no prediction.
  double smallest_free = 1.0;
  for (std::size_t j = 0; j < array.sensors.size(); ++j)
    if (array.sensors[j].kind == SensorKind::kLinear)
      smallest_free = std::min(smallest_free, 1.0 - leverages[j]);
  if (kinematics.residual.size() == 0 || !(smallest_free > 1e-6) ||
      kinematics.residual.maxCoeff() <= LinearFaultFloorG(config) * kStandardGravity * smallest_free)
    return {};
  const Index n = signals.size();
  std::vector<std::pair<double, std::size_t>> scored;
  std::vector<double> deleted(static_cast<std::size_t>(n));
  for (std::size_t j = 0; j < array.sensors.size(); ++j) {
    const Sensor& sensor = array.sensors[j];
    const int column = signals.FindSlot(sensor.slot);
    const double free = 1.0 - leverages[j];
    if (column < 0 || !(free > 1e-6)) continue;
    double largest = 0.0;
    for (Index k = 0; k < n; ++k) {
      const double value =
          std::abs(signals.samples(k, column) - PredictedReading(sensor, kinematics, k)) / free;
      deleted[static_cast<std::size_t>(k)] = value;
      largest = std::max(largest, value);
    }
    const double limit = InChannelUnits(sensor, LinearFaultFloorG(config), 0.0);
    if (!(largest > limit)) continue;
    const double sigma = 1.4826 * MedianInPlace(deleted);
    const double score = largest / std::max(limit, kFaultSigmas * sigma);
    if (score > 1.0) scored.emplace_back(score, j);
  }
  // The fault's omega error spreads over the other channels' deleted
  // residuals too: the few highest are tried, and the trial that leaves the
  // most rigid array decides.
  std::sort(scored.begin(), scored.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<std::size_t> suspects;
  for (std::size_t i = 0; i < std::min<std::size_t>(scored.size(), kLinearSuspectTrials); ++i)
    suspects.push_back(scored[i].second);
  return suspects;
}

// Two channels are confounded when leaving out either leaves the residual
// over the fault's interval within this factor as small, and each departs
// as a broken channel would: the array's redundancy cannot say which one
// broke (in the ideal 3-2-2-2, xarm_y and yarm_x share the one equation
// that checks alpha_z). Over the interval, not the record: on a noisy
// record both omissions leave the noise, which hides the fault's share.
constexpr double kTwinRmsFactor = 2.0;

// Whether omitting channels lowers the RMS residual from `recorded_rms` to
// `without_rms` enough to call them faulty (kFaultImprovement).
bool ExplainsFault(double recorded_rms, double without_rms) {
  return !std::isfinite(recorded_rms) || without_rms * kFaultImprovement <= recorded_rms;
}

// Where `sensor` departs from what the kinematics solved without it imply:
// the first and last sample beyond the threshold, and the largest departure
// (channel units).
struct Departure {
  Index first = -1, last = -1;
  double largest = 0.0;
  double sigma = 0.0;           // robust standard deviation of the departure (channel units)
  double predicted_peak = 0.0;  // largest |prediction| (channel units)
  double peak = 0.0;            // largest departure anywhere (channel units)
};

double FaultFloor(const Sensor& sensor, const Departure& departure, const ScreeningConfig& config);

Departure DepartureOf(const Sensor& sensor, const TestSignals& signals, const Kinematics& kinematics_without,
                      const ScreeningConfig& config) {
  Departure departure;
  const int column = signals.FindSlot(sensor.slot);
  if (column < 0 || kinematics_without.size() != signals.size()) return departure;
  const Index n = signals.size();
  std::vector<double> magnitude(static_cast<std::size_t>(n));
  for (Index k = 0; k < n; ++k) {
    const double predicted = PredictedReading(sensor, kinematics_without, k);
    departure.predicted_peak = std::max(departure.predicted_peak, std::abs(predicted));
    magnitude[static_cast<std::size_t>(k)] = std::abs(signals.samples(k, column) - predicted);
    departure.peak = std::max(departure.peak, magnitude[static_cast<std::size_t>(k)]);
  }
  const double sigma = 1.4826 * Median(magnitude);
  departure.sigma = sigma;
  const double threshold = std::max(
      kFaultSigmas * sigma, InChannelUnits(sensor, LinearFaultFloorG(config), config.bias_limit_radps));
  for (Index k = 0; k < n; ++k) {
    const double value = magnitude[static_cast<std::size_t>(k)];
    if (!(value > threshold)) continue;
    if (departure.first < 0) departure.first = k;
    departure.last = k;
    departure.largest = std::max(departure.largest, value);
  }
  // A fault over the whole record leaves no quiet samples to measure the
  // noise by: its interval is where it departs beyond the floor.
  if (departure.first < 0) {
    const double floor = FaultFloor(sensor, departure, config);
    for (Index k = 0; k < n; ++k) {
      if (!(magnitude[static_cast<std::size_t>(k)] > floor)) continue;
      if (departure.first < 0) departure.first = k;
      departure.last = k;
    }
  }
  return departure;
}

// The error finding of a faulty channel: its interval, its largest
// departure from the rigid body and the improvement its omission brings.
// Whether the departure says the channel is broken (kFaultSigmas, above).
// The floor: kFaultFloorFraction x residual_limit_g for a linear channel; for
// an angular-rate channel, predicted by integrating the linear channels'
// alpha and filtered otherwise (CFC 60 against CFC 1000), a tenth of its
// peak and bias_limit_radps.
double FaultFloor(const Sensor& sensor, const Departure& departure, const ScreeningConfig& config) {
  return sensor.kind == SensorKind::kLinear
             ? InChannelUnits(sensor, LinearFaultFloorG(config), 0.0)
             : std::max(InChannelUnits(sensor, 0.0, config.bias_limit_radps), 0.1 * departure.predicted_peak);
}

bool DepartsAsFault(const Sensor& sensor, const Departure& departure, const ScreeningConfig& config) {
  return departure.first >= 0 && departure.largest > FaultFloor(sensor, departure, config) &&
         departure.largest > kFaultSigmas * departure.sigma;
}

// A fault over the whole record (a swapped or flipped rate channel, a gain
// error) has no quiet samples to measure the noise by: there the residual's
// improvement (ExplainsFault) judges, with a departure beyond the floor.
bool DepartsBeyondFloor(const Sensor& sensor, const Departure& departure, const ScreeningConfig& config) {
  return departure.peak > FaultFloor(sensor, departure, config);
}

// Over the fault's interval, how many times smaller the rigid-body residual
// is without the channel: a broken channel leaves the others consistent to
// their noise there (tens to thousands of times smaller), a geometry that
// is only approximately right (nominal positions) spreads its misfit over
// every channel and improves about 2-fold.
constexpr double kFaultWindowImprovement = 4.0;
// ... and over the whole record at least this many times smaller (a sensor
// whose declared position is off departs at every fast rotation, improving
// the record less than 2-fold).
constexpr double kFaultRecordImprovement = 2.0;

// The RMS of `residual` over the departure's interval (+infinity without one).
double WindowRms(const Eigen::VectorXd& residual, const Departure& departure) {
  if (departure.first < 0 || departure.last >= residual.size())
    return std::numeric_limits<double>::infinity();
  const Index length = departure.last - departure.first + 1;
  return std::sqrt(residual.segment(departure.first, length).squaredNorm() / static_cast<double>(length));
}

// Whether leaving out another channel fits the fault's interval about as
// well as leaving out the culprit did (kTwinRmsFactor).
bool Confounded(const ArrayGeometry& array, const Sensor& culprit, const Sensor& other,
                const Eigen::VectorXd& without_culprit, const Departure& culprit_departure,
                const Eigen::VectorXd& without_other) {
  // Parallel columns of I - H are necessary (else the per-sample equations
  // already tell the two apart) but not sufficient: the centripetal terms
  // of the integrated omega can, which the fits over the interval show.
  if (ParallelInResidual(array, culprit, other) == false) return false;
  const double culprit_rms = WindowRms(without_culprit, culprit_departure);
  return std::isfinite(culprit_rms) &&
         WindowRms(without_other, culprit_departure) <= kTwinRmsFactor * culprit_rms;
}

bool WindowExplains(const Eigen::VectorXd& recorded_residual, const Eigen::VectorXd& without_residual,
                    const Departure& departure) {
  if (departure.first < 0 || recorded_residual.size() != without_residual.size() ||
      departure.last >= recorded_residual.size())
    return false;
  const Index length = departure.last - departure.first + 1;
  const double with = recorded_residual.segment(departure.first, length).squaredNorm();
  const double without = without_residual.segment(departure.first, length).squaredNorm();
  if (!std::isfinite(with)) return true;
  const double record_with = recorded_residual.squaredNorm();
  const double record_without = without_residual.squaredNorm();
  return without * kFaultWindowImprovement * kFaultWindowImprovement <= with &&
         record_without * kFaultRecordImprovement * kFaultRecordImprovement <= record_with;
}

// The error findings of two confounded channels (kTwinRmsFactor): one per
// channel, each naming both, so that salvage takes both or neither.
void AddConfoundedFindings(const Sensor& first, const Sensor& second, double recorded_rms, double without_rms,
                           std::vector<Finding>& findings) {
  const std::string detail =
      "channels " + first.slot + " and " + second.slot +
      " are inconsistent with a rigid body and cannot be told apart: leaving out either "
      "lowers the RMS rigid-body residual " +
      FromTo(recorded_rms, without_rms) +
      ", and the array has no redundant equation to decide which one is faulty.";
  findings.push_back(MakeFinding(Check::kFault, first.slot, Severity::kError, detail));
  findings.push_back(MakeFinding(Check::kFault, second.slot, Severity::kError, detail));
}

Finding FaultFinding(const Sensor& sensor, const std::optional<std::string>& partner,
                     const TestSignals& signals, const Kinematics& kinematics_without, double recorded_rms,
                     double without_rms, const ScreeningConfig& config) {
  const Departure departure = DepartureOf(sensor, signals, kinematics_without, config);
  std::ostringstream detail;
  detail << "channel " << sensor.slot << " is faulty";
  if (departure.first >= 0)
    detail << " from t = " << Number(kinematics_without.time_s(departure.first), 6)
           << " s to t = " << Number(kinematics_without.time_s(departure.last), 6)
           << " s (it departs by up to " << Number(departure.peak) << " " << sensor.unit
           << " from what the other channels imply for a rigid body)";
  detail << ": leaving it out" << (partner ? " with channel " + *partner : std::string())
         << " lowers the RMS rigid-body residual " << FromTo(recorded_rms, without_rms) << ".";
  return MakeFinding(Check::kFault, sensor.slot, Severity::kError, detail.str());
}

std::optional<Culprit> LeaveOneOut(const ArrayGeometry& array, const TestSignals& signals,
                                   const SolveOptions& options, double recorded_rms, double limit_mps2) {
  Culprit best;
  best.rms_mps2 = recorded_rms;
  best.runner_up_rms_mps2 = recorded_rms;
  Kinematics kinematics;
  for (std::size_t i = 0; i < array.sensors.size(); ++i) {
    const std::optional<ArrayGeometry> reduced = CheckableWithout(array, {i});
    if (!reduced) continue;
    const ResidualFit fit = SolveResidual(*reduced, signals, options, kinematics);
    if (!fit.solved || !(fit.rms < best.runner_up_rms_mps2)) continue;
    // The next trial reuses the storage of the solve that drops out.
    if (fit.rms < best.rms_mps2) {
      std::swap(best.runner_up_kinematics, best.kinematics);
      best.runner_up = best.sensor;
      best.runner_up_rms_mps2 = best.rms_mps2;
      best.sensor = &array.sensors[i];
      best.rms_mps2 = fit.rms;
      std::swap(best.kinematics, kinematics);
    } else {
      best.runner_up = &array.sensors[i];
      best.runner_up_rms_mps2 = fit.rms;
      std::swap(best.runner_up_kinematics, kinematics);
    }
  }
  if (best.sensor == nullptr) return std::nullopt;
  best.accounts = std::isfinite(recorded_rms) ? best.rms_mps2 < kLeaveOutFraction * recorded_rms
                                              : best.rms_mps2 < limit_mps2;
  return best;
}

// The residual finding: where it peaks (or the solve diverges) and which
// channel, if any, accounts for it.
Finding ResidualFinding(const ResidualStatistics& residual, const Kinematics& kinematics,
                        const std::optional<Culprit>& culprit, double limit_g) {
  std::ostringstream detail;
  if (std::isfinite(residual.peak_mps2))
    detail << "the rigid-body residual of the exact solver peaks at "
           << Number(residual.peak_mps2 / kStandardGravity)
           << " g at t = " << Number(kinematics.time_s(residual.peak_at), 6) << " s, beyond the "
           << Number(limit_g) << " g limit";
  else
    detail << "the exact solver diverges at t = " << Number(kinematics.time_s(residual.peak_at), 6)
           << " s (the channels are far from a rigid body)";
  std::optional<std::string> culprit_slot;
  if (culprit) culprit_slot = culprit->sensor->slot;
  if (culprit_slot)
    detail << "; leaving out channel " << *culprit_slot << " lowers the RMS residual "
           << FromTo(residual.rms_mps2, culprit->rms_mps2) << ".";
  else if (std::isfinite(residual.rms_mps2))
    detail << " (RMS " << Number(residual.rms_mps2 / kStandardGravity)
           << " g) and no single channel accounts for it.";
  else
    detail << " and no single channel accounts for it.";
  return MakeFinding(Check::kResidual, culprit_slot, Severity::kWarning, detail.str());
}

}  // namespace

double PredictedReading(const Sensor& sensor, const Kinematics& kinematics, Index k) {
  const Eigen::Vector3d omega = kinematics.omega_body.row(k).transpose();
  if (sensor.kind == SensorKind::kAngularRate) return sensor.axis_body.dot(omega) / sensor.si_per_unit;
  const Eigen::Vector3d alpha = kinematics.alpha_body.row(k).transpose();
  const Eigen::Vector3d& r = sensor.position_body_m;
  const Eigen::Vector3d point_acc =
      kinematics.acc_body.row(k).transpose() + alpha.cross(r) + omega.cross(omega.cross(r));
  return sensor.axis_body.dot(point_acc) / sensor.si_per_unit;
}

bool IsFatal(const Finding& finding) {
  return finding.severity == Severity::kError &&
         (finding.check == NameOf(Check::kMissing) || finding.check == NameOf(Check::kNonFinite));
}

void AppendFindings(const std::vector<Finding>& more, std::vector<Finding>& findings) {
  for (const Finding& finding : more) {
    const bool known = std::any_of(findings.begin(), findings.end(), [&](const Finding& existing) {
      return existing.check == finding.check && existing.channel == finding.channel;
    });
    if (!known) findings.push_back(finding);
  }
}

int ResidualRedundancy(const ArrayGeometry& array) {
  ArrayGeometry validated = array;
  ValidateArray(validated);
  const int linear = static_cast<int>(validated.LinearIndices().size());
  switch (ClassifyArray(validated)) {
    case ExactPath::kLinear:
      return linear - 6;  // L equations, unknowns a and alpha
    case ExactPath::kSixAOmega:
      return linear - 3;  // L equations, unknown a (omega, alpha from the rates)
    case ExactPath::kFused:
      return linear + 3 - 6;  // L + 3 differentiated-rate equations, unknowns a and alpha
    case ExactPath::kAccelerationOnly:
      return 0;  // without omega no rigid-body equation can be checked
  }
  return 0;
}

std::vector<Finding> ScreenConsistency(const ArrayGeometry& array, const TestSignals& conditioned_signals,
                                       const Kinematics& exact_kinematics, const SolveOptions& exact_options,
                                       const ScreeningConfig& config) {
  std::vector<Finding> findings;
  if (ResidualRedundancy(array) <= 0) {
    findings.push_back(MakeFinding(Check::kConsistency, std::nullopt, Severity::kInfo,
                                   "array " + array.name +
                                       " has no redundant channel, so polarity, axis-label and "
                                       "rigid-body residual checks are not possible."));
    return findings;
  }
  if (exact_kinematics.size() == 0) return findings;
  const double limit_mps2 = config.residual_limit_g * kStandardGravity;
  const ResidualStatistics residual = StatisticsOf(exact_kinematics);
  // A zero offset on one channel leaves a steady residual of about the
  // offset (times the channel's share of the redundancy), often below the
  // peak limit: a median residual above half the bias limit also starts
  // the search for the channel at fault.
  const bool over_limit = residual.peak_mps2 > limit_mps2;
  const bool steady = !(residual.median_mps2 <= 0.5 * config.bias_limit_g * kStandardGravity);
  // A broken channel whose residual the least squares hides in alpha can
  // peak below the limit while the motion is badly wrong: the search for
  // a faulty channel starts at kFaultPeakFraction of it.
  const bool suspect = residual.peak_mps2 > kFaultPeakFraction * limit_mps2;
  const SolveOptions options = TrialOptions(exact_options);
  if (!suspect && !steady) {
    // A low residual can still hide a broken channel of high leverage: one
    // trial solve, for the channel the deleted residuals point to.
    std::vector<std::size_t> candidates =
        LinearSuspects(array, conditioned_signals, exact_kinematics, config);
    // A fused array takes omega from its rate sensors: a broken one moves
    // omega while the residual (which weights the differentiated rates
    // lightly) hardly shows it; each is checked against the omega the
    // linear channels integrate.
    ArrayGeometry validated = array;
    ValidateArray(validated);
    if (ClassifyArray(validated) == ExactPath::kFused)
      for (const std::size_t index : array.RateIndices()) candidates.push_back(index);
    struct Faulty {
      const Sensor* sensor;
      double rms_mps2;
      Kinematics without;
      Departure departure;
    };
    std::vector<Faulty> faulty;
    for (const std::size_t index : candidates) {
      ArrayGeometry reduced = array;
      reduced.sensors.erase(reduced.sensors.begin() + static_cast<std::ptrdiff_t>(index));
      Kinematics without;
      const ResidualFit fit = SolveResidual(reduced, conditioned_signals, options, without);
      const Sensor& sensor = array.sensors[index];
      if (!fit.solved) continue;
      const Departure departure = DepartureOf(sensor, conditioned_signals, without, config);
      const bool whole_record =
          DepartsBeyondFloor(sensor, departure, config) && ExplainsFault(residual.rms_mps2, fit.rms);
      if (((DepartsAsFault(sensor, departure, config) &&
            WindowExplains(exact_kinematics.residual, without.residual, departure)) ||
           whole_record) &&
          !ExplainAsOffset(sensor, conditioned_signals, without, config))
        faulty.push_back({&sensor, fit.rms, std::move(without), departure});
    }
    std::sort(faulty.begin(), faulty.end(),
              [](const Faulty& a, const Faulty& b) { return a.rms_mps2 < b.rms_mps2; });
    if (faulty.size() >= 2 &&
        Confounded(array, *faulty[0].sensor, *faulty[1].sensor, faulty[0].without.residual,
                   faulty[0].departure, faulty[1].without.residual))
      AddConfoundedFindings(*faulty[0].sensor, *faulty[1].sensor, residual.rms_mps2, faulty[1].rms_mps2,
                            findings);
    else if (!faulty.empty())
      findings.push_back(FaultFinding(*faulty[0].sensor, std::nullopt, conditioned_signals, faulty[0].without,
                                      residual.rms_mps2, faulty[0].rms_mps2, config));
    return findings;
  }

  // Polarity and axis labels (report section 3.4: "as a check for correct
  // polarity and axis labeling"). Much better: a fraction of the recorded
  // RMS residual and an RMS within the per-sample limit (the hypothesis
  // must explain the inconsistency, not merely reduce it: a gain error on
  // another channel is no swap).
  if (over_limit) {
    const Hypothesis best = BestHypothesis(array, conditioned_signals, options, residual.rms_mps2);
    const bool much_better =
        best.rms_mps2 < kHypothesisFraction * residual.rms_mps2 && best.rms_mps2 < limit_mps2;
    if (best.finding && much_better) {
      findings.push_back(*best.finding);
      if (best.partner) {
        // One finding per channel of the pair, each naming both.
        Finding partner = *best.finding;
        partner.channel = best.partner;
        findings.push_back(std::move(partner));
      }
    }
  }

  // The residual itself, with the channel whose omission removes most of it.
  const std::optional<Culprit> culprit =
      LeaveOneOut(array, conditioned_signals, options, residual.rms_mps2, limit_mps2);
  const bool flip_or_swap = std::any_of(findings.begin(), findings.end(), [](const Finding& finding) {
    return finding.check == NameOf(Check::kPolarity) || finding.check == NameOf(Check::kAxisLabel);
  });
  bool offset_found = false;
  if (culprit && culprit->accounts) {
    if (std::optional<Finding> offset =
            ExplainAsOffset(*culprit->sensor, conditioned_signals, culprit->kinematics, config)) {
      findings.push_back(std::move(*offset));
      offset_found = true;
    }
  }
  // A faulty channel (docs/algorithms.md "Faulty channels"): never published.
  // A zero offset stays the bias warning (conditioning's bias removal is its
  // remedy), a flip or swap its own error finding.
  if (!flip_or_swap && !offset_found) {
    bool single = culprit && ExplainsFault(residual.rms_mps2, culprit->rms_mps2);
    if (culprit && !single) {
      const Departure departure =
          DepartureOf(*culprit->sensor, conditioned_signals, culprit->kinematics, config);
      single = DepartsAsFault(*culprit->sensor, departure, config) &&
               WindowExplains(exact_kinematics.residual, culprit->kinematics.residual, departure);
    }
    // Two broken channels: no single omission leaves a rigid body (the
    // residual without the best single channel still peaks above the
    // search's threshold), one pair's omission does, 10-fold better.
    const bool single_leaves_residual =
        !culprit || !(culprit->kinematics.residual.size() > 0 &&
                      culprit->kinematics.residual.maxCoeff() <= kFaultPeakFraction * limit_mps2);
    std::optional<CulpritPair> pair;
    if (single_leaves_residual && ResidualRedundancy(array) >= 3) {
      pair = LeaveTwoOut(array, conditioned_signals, options, residual.rms_mps2);
      if (pair && !(ExplainsFault(residual.rms_mps2, pair->rms_mps2) &&
                    (!culprit || pair->rms_mps2 * kFaultImprovement <= culprit->rms_mps2)))
        pair.reset();
    }
    if (pair) {
      findings.push_back(FaultFinding(*pair->first, pair->second->slot, conditioned_signals, pair->kinematics,
                                      residual.rms_mps2, pair->rms_mps2, config));
      findings.push_back(FaultFinding(*pair->second, pair->first->slot, conditioned_signals, pair->kinematics,
                                      residual.rms_mps2, pair->rms_mps2, config));
    } else if (single) {
      // A runner-up that fits as well and departs as a broken channel would
      // is its confounded twin (kTwinRmsFactor).
      const bool confounded =
          culprit->runner_up != nullptr &&
          Confounded(array, *culprit->sensor, *culprit->runner_up, culprit->kinematics.residual,
                     DepartureOf(*culprit->sensor, conditioned_signals, culprit->kinematics, config),
                     culprit->runner_up_kinematics.residual) &&
          DepartsBeyondFloor(
              *culprit->runner_up,
              DepartureOf(*culprit->runner_up, conditioned_signals, culprit->runner_up_kinematics, config),
              config);
      if (confounded)
        AddConfoundedFindings(*culprit->sensor, *culprit->runner_up, residual.rms_mps2,
                              culprit->runner_up_rms_mps2, findings);
      else
        findings.push_back(FaultFinding(*culprit->sensor, std::nullopt, conditioned_signals,
                                        culprit->kinematics, residual.rms_mps2, culprit->rms_mps2, config));
    }
  }
  if (over_limit)
    findings.push_back(ResidualFinding(residual, exact_kinematics,
                                       culprit && culprit->accounts ? culprit : std::optional<Culprit>(),
                                       config.residual_limit_g));
  return findings;
}

std::vector<Finding> ScreenPlausibility(const Kinematics& kinematics, const Eigen::VectorXd& exact_residual,
                                        const ProcessingConfig& config) {
  std::vector<Finding> findings;
  const PlausibilityConfig& limits = config.plausibility;
  auto peak = [&](const Eigen::VectorXd& norm, double scale, double limit, const char* channel,
                  const char* what, const char* unit) {
    if (norm.size() == 0) return;
    Index worst = 0;
    const double value = norm.maxCoeff(&worst) * scale;
    if (!(value > limit)) return;
    findings.push_back(MakeFinding(Check::kImplausible, std::string(channel), Severity::kError,
                                   "the solved " + std::string(what) + " reaches " + Number(value, 6) + unit +
                                       " at sample " + std::to_string(worst) +
                                       " (t = " + Number(kinematics.time_s(worst), 6) +
                                       " s), beyond the plausibility limit of " + Number(limit, 6) + unit +
                                       ": check the channels (corrupt samples, units, initial state)."));
  };
  peak(kinematics.acc_body.rowwise().norm(), 1.0 / kStandardGravity, limits.max_acceleration_g, "acc_cg",
       "head CG acceleration", " g");
  peak(kinematics.omega_body.rowwise().norm(), 1.0, limits.max_angular_velocity_radps, "omega",
       "angular velocity", " rad/s");
  if (exact_residual.size() == kinematics.size())
    peak(exact_residual, 1.0 / kStandardGravity,
         limits.max_residual_factor * config.screening.residual_limit_g, "residual", "rigid-body residual",
         " g");
  return findings;
}

}  // namespace napkin::engine
