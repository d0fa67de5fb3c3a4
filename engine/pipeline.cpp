#include "engine/pipeline.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/error.h"
#include "engine/cancellation.h"
#include "engine/criteria.h"
#include "engine/exact_solver.h"
#include "engine/screening.h"
#include "engine/solver.h"

namespace napkin::engine {
namespace {

// First sample whose solved kinematics are not finite, or -1.
// Acceleration-only kinematics are NaN by design wherever they need the
// rotation (engine/kinematics.h HasRotation): only acc_body is checked there.
Eigen::Index FirstNonFinite(const Kinematics& kinematics) {
  const bool rotation = HasRotation(kinematics);
  for (Eigen::Index k = 0; k < kinematics.size(); ++k) {
    if (!kinematics.acc_body.row(k).allFinite()) return k;
    if (rotation && (!kinematics.omega_body.row(k).allFinite() || !kinematics.acc_fixed.row(k).allFinite() ||
                     !kinematics.alpha_body.row(k).allFinite() || !kinematics.pos_fixed.row(k).allFinite()))
      return k;
  }
  return -1;
}

// The info finding of a test whose array cannot determine rotation.
Finding RotationUndetermined(const ArrayGeometry& array) {
  return Finding{NameOf(Check::kRotation), std::nullopt, Severity::kInfo,
                 "array " + array.name +
                     " cannot determine rotation from its sensors (neither six independent linear "
                     "rigid-body equations nor angular-rate sensors on three axes): the results hold the CG "
                     "acceleration and HIC, peak and a3ms from it; angular velocity and acceleration, BrIC, "
                     "DAMAGE, orientation, velocity and position are null, and the rigid-body consistency "
                     "checks are skipped."};
}

// The first error-severity finding, or nullptr: the verdict's rule.
const Finding* FirstError(const std::vector<Finding>& findings) {
  const auto error = std::find_if(findings.begin(), findings.end(),
                                  [](const Finding& f) { return f.severity == Severity::kError; });
  return error == findings.end() ? nullptr : &*error;
}

// Sampling interval beyond which a time base is taken as corrupt (1 ns:
// 1 GHz, far above any crash-test recorder; docs/algorithms.md "Physical
// plausibility").
constexpr double kMinSamplingIntervalS = 1e-9;

// Refuses, before any numerics, a time base or initial state that no real
// test has, with a sentence saying which value is wrong (rather than letting
// the solver blame the channels).
void CheckTimeBaseAndInitialState(const TestSignals& signals, const InitialState& initial,
                                  const ProcessingConfig& config) {
  std::ostringstream message;
  if (!(std::isfinite(signals.dt_s) && signals.dt_s > 0.0)) {
    message << "the sampling interval " << signals.dt_s << " s is not a finite positive number.";
  } else if (signals.dt_s < kMinSamplingIntervalS) {
    message << "the sampling interval " << signals.dt_s << " s is below " << kMinSamplingIntervalS
            << " s (a sampling rate above 1 GHz): the time base is corrupt; check the time column or "
            << "the file's sampling interval.";
  } else if (!std::isfinite(signals.t0_s)) {
    message << "the time of the first sample is not a finite number.";
  } else if (!initial.velocity_fixed_mps.allFinite() ||
             initial.velocity_fixed_mps.norm() > config.plausibility.max_initial_speed_mps) {
    message << "the initial velocity (" << initial.velocity_fixed_mps.transpose() << ") m/s is beyond the "
            << "plausibility limit of " << config.plausibility.max_initial_speed_mps
            << " m/s; check --initial-velocity (m/s).";
  } else if (!initial.omega_body_radps.allFinite() ||
             initial.omega_body_radps.norm() > config.plausibility.max_angular_velocity_radps) {
    message << "the initial angular velocity (" << initial.omega_body_radps.transpose()
            << ") rad/s is beyond the plausibility limit of "
            << config.plausibility.max_angular_velocity_radps << " rad/s.";
  } else if (!initial.orientation_rad.allFinite()) {
    message << "the initial orientation is not finite; check --orientation (rad).";
  } else {
    return;
  }
  throw InputError(message.str());
}

// The signals to condition: a copy of `raw` into `copy` (the workspace's:
// its memory reused when as large) made a channel at a time, looking at
// `cancel` between two (copying a long record's channels into fresh memory
// takes most of a second). Every field of TestSignals (engine/signals.h) is
// copied.
void CopyToCondition(const TestSignals& raw, TestSignals& copy, const std::atomic<bool>* cancel) {
  copy.dt_s = raw.dt_s;
  copy.t0_s = raw.t0_s;
  copy.slots = raw.slots;
  copy.prefiltered_cfc = raw.prefiltered_cfc;
  copy.file_rows = raw.file_rows;
  copy.samples.resize(raw.samples.rows(), raw.samples.cols());
  for (Eigen::Index c = 0; c < raw.samples.cols(); ++c) {
    ThrowIfCancelled(cancel);
    copy.samples.col(c) = raw.samples.col(c);
  }
}

// ProcessTest after the raw-signal screening that found `findings`, into
// `processed` (in `workspace`'s memory).
void ProcessScreened(const ArrayGeometry& array, const TestSignals& raw_signals, const InitialState& initial,
                     const ProcessingConfig& config, std::vector<Finding> findings,
                     const std::atomic<bool>* cancel, Workspace& workspace, ProcessedTest& processed) {
  TestSignals& signals = workspace.signals;
  CopyToCondition(raw_signals, signals, cancel);
  processed.summary = TestSummary{};
  processed.summary.conditioning = ApplyConditioning(array, signals, config, cancel, &workspace.filter_work);
  AppendFindings(ConditioningFindings(processed.summary.conditioning), findings);
  ThrowIfCancelled(cancel);
  SolveOptions options = MakeSolveOptions(config, initial);
  options.cancel = cancel;
  Solve(array, signals, options, processed.kinematics);
  ThrowIfCancelled(cancel);

  // Rigid-body consistency is judged by the exact solver's residual, also
  // when the result comes from the seed solver. Without rotation there is
  // nothing to judge it by (docs/algorithms.md "Acceleration-only arrays").
  const Eigen::VectorXd* exact_residual = nullptr;
  ArrayGeometry validated = array;
  ValidateArray(validated);
  if (!DeterminesRotation(validated)) {
    findings.push_back(RotationUndetermined(validated));
  } else if (options.solver == SolverKind::kExact) {
    AppendFindings(ScreenConsistency(array, signals, processed.kinematics, options, config.screening),
                   findings);
    exact_residual = &processed.kinematics.residual;
  } else {
    SolveOptions exact_options = options;
    exact_options.solver = SolverKind::kExact;
    Solve(array, signals, exact_options, workspace.exact);
    AppendFindings(ScreenConsistency(array, signals, workspace.exact, exact_options, config.screening),
                   findings);
    exact_residual = &workspace.exact.residual;
  }
  ThrowIfCancelled(cancel);

  // Signals far from a rigid body (a flipped or swapped channel of a
  // linear-only array) can make the integrated angular velocity diverge:
  // there is no result to flag, so stop, naming what screening found.
  const Eigen::Index diverged_at = FirstNonFinite(processed.kinematics);
  if (diverged_at >= 0) {
    std::ostringstream message;
    message << "the solved kinematics diverge at sample " << diverged_at
            << " (t = " << processed.kinematics.time_s(diverged_at)
            << " s) because the channels are inconsistent with a rigid "
            << "body";
    if (const Finding* error = FirstError(findings)) {
      std::string reason = error->detail;
      if (!reason.empty() && reason.back() == '.') reason.pop_back();
      message << " (screening: " << reason << ")";
    }
    message << ".";
    throw ScreeningFailure(message.str(), std::move(findings));
  }

  // A finite but physically absurd result is no result (README "What it
  // computes": screening): it fails the test like any error finding.
  const Eigen::VectorXd no_residual;
  AppendFindings(
      ScreenPlausibility(
          processed.kinematics,
          exact_residual != nullptr && exact_residual->allFinite() ? *exact_residual : no_residual, config),
      findings);
  ThrowIfCancelled(cancel);

  SummarizeKinematics(processed.kinematics, processed.summary);
  ThrowIfCancelled(cancel);
  FillCriteria(processed.kinematics, config, processed.summary, cancel, &workspace.criteria);
  processed.summary.findings = std::move(findings);
}

}  // namespace

ProcessedTest ProcessTest(const ArrayGeometry& array, const TestSignals& raw_signals,
                          const InitialState& initial, const ProcessingConfig& config,
                          const std::atomic<bool>* cancel) {
  Workspace workspace;
  ProcessedTest processed;
  ProcessTest(array, raw_signals, initial, config, workspace, processed, cancel);
  return processed;
}

void ProcessTest(const ArrayGeometry& array, const TestSignals& raw_signals, const InitialState& initial,
                 const ProcessingConfig& config, Workspace& workspace, ProcessedTest& out,
                 const std::atomic<bool>* cancel) {
  config.Check();
  CheckTimeBaseAndInitialState(raw_signals, initial, config);
  ThrowIfCancelled(cancel);
  // Screening runs on the raw signals first (report section 2.2: check the
  // data before using them). A missing channel or a non-finite sample makes
  // the test unusable: stop with the finding's sentence (slot, sample, time).
  std::vector<Finding> findings = ScreenSignals(array, raw_signals, initial, config);
  const auto fatal = std::find_if(findings.begin(), findings.end(), IsFatal);
  if (fatal != findings.end()) {
    std::string sentence = fatal->detail;
    throw ScreeningFailure(sentence, std::move(findings));
  }
  ThrowIfCancelled(cancel);

  // A raw sample beyond the plausibility limits fails the test with its
  // finding (FailingFinding). Should the computation stop on it first
  // (1e300 g overflows once squared), the sentence would name a sample of
  // the filtered signal, hundreds of samples and milliseconds away from the
  // recorded one (issue 29 point 11): the test stops with the raw finding,
  // which names the recorded sample, its time and its file row.
  const auto implausible = std::find_if(findings.begin(), findings.end(), [](const Finding& finding) {
    return finding.severity == Severity::kError && finding.check == NameOf(Check::kImplausible);
  });
  if (implausible == findings.end())
    return ProcessScreened(array, raw_signals, initial, config, std::move(findings), cancel, workspace, out);
  const std::string cause = implausible->detail;
  std::vector<Finding> screened = findings;  // what the failure carries should the computation stop
  try {
    ProcessScreened(array, raw_signals, initial, config, std::move(findings), cancel, workspace, out);
  } catch (const InputError&) {
    throw ScreeningFailure(cause, std::move(screened));
  }
}

std::uint64_t ProcessTestBytes(const ArrayGeometry& array, Eigen::Index samples, double dt_s,
                               const ProcessingConfig& config) {
  if (samples <= 0) return 0;
  // Counted in columns of `samples` doubles (one series component each).
  ArrayGeometry validated = array;
  bool rotation = true;  // an array that cannot be validated: assume the larger kinematics
  ExactPath path = ExactPath::kLinear;
  try {
    ValidateArray(validated);
    rotation = DeterminesRotation(validated);
    path = ClassifyArray(validated);
  } catch (const InputError&) {
  }
  const auto slots = static_cast<double>(array.sensors.size());
  std::size_t linear = 0, rates = 0;
  for (const Sensor& sensor : array.sensors) (sensor.kind == SensorKind::kLinear ? linear : rates) += 1;
  const double n = static_cast<double>(samples);

  // Held to the end: the conditioned copy of the signals and the kinematics
  // (engine/kinematics.h: 1 + 10 x 3 + 4 + 1 series; time and acc_body only
  // without rotation).
  const double kinematics = rotation ? 36.0 : 4.0;
  const double held = slots + kinematics;
  // Conditioning: each filter in use pads its channels by up to
  // max(padding_s, 1 / CFC) at both ends and runs four channels abreast.
  double filtering = 0.0;
  const auto filter_columns = [&](std::size_t count, const std::optional<double>& cfc) {
    if (count == 0 || !cfc || !(dt_s > 0.0)) return 0.0;
    const double pad = std::min(std::ceil(std::max(config.filter.padding_s, 1.0 / *cfc) / dt_s), n - 1.0);
    return 4.0 * (n + 2.0 * pad) / n;
  };
  filtering += filter_columns(linear, config.filter.linear_cfc);
  filtering += filter_columns(rates, config.filter.angular_rate_cfc);
  // The solver's own series: the channels sample by sample (rates and
  // linear), omega and its derivative; the seed solver's REAL*4 listing
  // (about 20 columns) and, alongside its result, the exact solve that
  // judges its consistency.
  double solving = 3.0 * slots + 12.0;
  if (path == ExactPath::kSixAOmega || path == ExactPath::kFused) solving += slots + 9.0;
  if (config.solver == SolverKind::kSeed) solving += 20.0 + kinematics;
  // Criteria: the resultant, the HIC integral and its segment tree (three
  // arrays of twice the next power of two), DAMAGE's displacement.
  const double leaves = std::exp2(std::ceil(std::log2(std::max(n, 1.0))));
  const double criteria = 2.0 + 6.0 * leaves / n + 9.0;
  const double columns = held + std::max({filtering, solving, criteria});
  // Plus a fixed allowance for the findings, the summary and the allocator.
  constexpr double kFixedBytes = 16.0 * (1 << 20);
  return static_cast<std::uint64_t>(
      std::ceil(columns * n * static_cast<double>(sizeof(double)) + kFixedBytes));
}

const Finding* FailingFinding(const ProcessedTest& processed) {
  return FirstError(processed.summary.findings);
}

}  // namespace napkin::engine
