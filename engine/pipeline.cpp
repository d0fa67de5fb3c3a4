#include "engine/pipeline.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include "common/error.h"
#include "engine/cancellation.h"
#include "engine/criteria.h"
#include "engine/exact_solver.h"
#include "engine/finite_samples.h"
#include "engine/salvage.h"
#include "engine/screening.h"
#include "engine/solver.h"
#include "engine/units.h"

namespace napkin::engine {
namespace {

// First sample whose solved kinematics are not finite, or -1.
// Acceleration-only kinematics are NaN by design wherever they need the
// rotation (engine/kinematics.h HasRotation): only acc_body is checked there.
Eigen::Index FirstNonFinite(const Kinematics& kinematics) {
  const bool rotation = HasRotation(kinematics);
  // Finite series (every solved test's) are told by one vectorised pass over
  // each column (internal::AllFinite); the walk along the rows, across the
  // columns of five series, only looks for the sample where they are not.
  using internal::AllFinite;
  if (AllFinite(kinematics.acc_body) &&
      (!rotation || (AllFinite(kinematics.omega_body) && AllFinite(kinematics.acc_fixed) &&
                     AllFinite(kinematics.alpha_body) && AllFinite(kinematics.pos_fixed))))
    return -1;
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

// The first error-severity finding, or nullptr: the rule that fails a test.
const Finding* FirstError(const std::vector<Finding>& findings) {
  const auto error = std::find_if(findings.begin(), findings.end(),
                                  [](const Finding& f) { return f.severity == Severity::kError; });
  return error == findings.end() ? nullptr : &*error;
}

// RMS of a residual series; +infinity when the solve diverged.
double RmsOf(const Eigen::VectorXd& residual) {
  if (residual.size() == 0) return 0.0;
  const double rms = std::sqrt(residual.squaredNorm() / static_cast<double>(residual.size()));
  return std::isfinite(rms) ? rms : std::numeric_limits<double>::infinity();
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
                     const std::atomic<bool>* cancel, Workspace& workspace, ProcessedTest& processed,
                     bool summary_series_only) {
  TestSignals& signals = workspace.signals;
  CopyToCondition(raw_signals, signals, cancel);
  processed.summary = TestSummary{};
  processed.summary.conditioning = ApplyConditioning(array, signals, config, cancel, &workspace.filter_work);
  AppendFindings(ConditioningFindings(processed.summary.conditioning), findings);
  ThrowIfCancelled(cancel);
  SolveOptions options = MakeSolveOptions(config, initial);
  options.cancel = cancel;
  options.summary_series_only = summary_series_only;
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
    exact_residual = &processed.kinematics.residual;
    workspace.exact_rms_residual_mps2 = RmsOf(*exact_residual);
    AppendFindings(ScreenConsistency(array, signals, processed.kinematics, options, config.screening),
                   findings);
  } else {
    SolveOptions exact_options = options;
    exact_options.solver = SolverKind::kExact;
    Solve(array, signals, exact_options, workspace.exact);
    exact_residual = &workspace.exact.residual;
    workspace.exact_rms_residual_mps2 = RmsOf(*exact_residual);
    AppendFindings(ScreenConsistency(array, signals, workspace.exact, exact_options, config.screening),
                   findings);
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
          exact_residual != nullptr && internal::AllFinite(*exact_residual) ? *exact_residual : no_residual,
          config),
      findings);
  ThrowIfCancelled(cancel);

  SummarizeKinematics(processed.kinematics, processed.summary);
  ThrowIfCancelled(cancel);
  FillCriteria(processed.kinematics, config, processed.summary, cancel, &workspace.criteria);
  processed.summary.findings = std::move(findings);
}

// ProcessTest without salvage.
void ProcessOnce(const ArrayGeometry& array, const TestSignals& raw_signals, const InitialState& initial,
                 const ProcessingConfig& config, Workspace& workspace, ProcessedTest& out,
                 const std::atomic<bool>* cancel, bool summary_series_only) {
  workspace.exact_rms_residual_mps2 = std::numeric_limits<double>::quiet_NaN();
  CheckTimeBaseAndInitialState(raw_signals, initial, config);
  ThrowIfCancelled(cancel);
  // Screening runs on the raw signals first (report section 2.2: check the
  // data before using them). A missing channel or a non-finite sample makes
  // the test unusable: stop with the finding's sentence (slot, sample, time).
  std::vector<Finding> findings = ScreenSignals(array, raw_signals, initial, config, cancel);
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
    return ProcessScreened(array, raw_signals, initial, config, std::move(findings), cancel, workspace, out,
                           summary_series_only);
  const std::string cause = implausible->detail;
  std::vector<Finding> screened = findings;  // what the failure carries should the computation stop
  try {
    ProcessScreened(array, raw_signals, initial, config, std::move(findings), cancel, workspace, out,
                    summary_series_only);
  } catch (const InputError&) {
    throw ScreeningFailure(cause, std::move(screened));
  }
}

// --- salvage (engine/salvage.h, docs/algorithms.md "Faulty channels") -----

std::string WithoutFinalStop(std::string sentence) {
  if (!sentence.empty() && sentence.back() == '.') sentence.pop_back();
  return sentence;
}

// "zarm_y" or "zarm_y and cg_x".
std::string ChannelList(const std::vector<std::string>& names) {
  std::string list;
  for (std::size_t i = 0; i < names.size(); ++i)
    list += (i == 0 ? "" : i + 1 == names.size() ? " and " : ", ") + names[i];
  return list;
}

std::string SalvageNumber(double value, int digits = 4) {
  std::ostringstream out;
  out << std::setprecision(digits) << value;
  return out.str();
}

// With salvage off: what `--config salvage` would do with the faulty
// channels, as the tail of the failing sentence (" — ...").
// Why salvage cannot recover a test whose faulty channels are `names`, as
// the tail of a sentence (" — salvage cannot recover ..."); nullopt when it can.
std::optional<std::string> SalvageImpossible(const ArrayGeometry& array,
                                             const std::vector<std::string>& names) {
  const std::string list = ChannelList(names);
  if (names.size() > static_cast<std::size_t>(kMaxSalvagedChannels))
    return " — salvage cannot recover the test: " + std::to_string(names.size()) + " channels are faulty (" +
           list + "), more than the " + std::to_string(kMaxSalvagedChannels) + " it repairs";
  std::string why;
  if (!ArrayWithout(array, names, why))
    return " — salvage cannot recover " + list + ": without " + (names.size() > 1 ? "them" : "it") + ", " +
           why;
  return std::nullopt;
}

std::string SalvageHint(const ArrayGeometry& array, const std::vector<FaultyChannel>& faults) {
  const std::vector<std::string> names = FaultyChannelNames(faults);
  if (std::optional<std::string> impossible = SalvageImpossible(array, names)) return *impossible;
  const std::string them = names.size() > 1 ? "them" : "it";
  return " — `--config salvage` would repair " + ChannelList(names) + " from the other channels (" +
         std::to_string(array.sensors.size() - names.size()) + " of " + std::to_string(array.sensors.size()) +
         " channels determine the motion without " + them + "; screening.salvage \"exclude\" would leave " +
         them + " out)";
}

// Appends the hint to the error findings of the faulty channels.
void AddSalvageHint(std::vector<Finding>& findings, const std::vector<FaultyChannel>& faults,
                    const std::string& hint) {
  const std::vector<std::string> names = FaultyChannelNames(faults);
  for (Finding& finding : findings)
    if (finding.severity == Severity::kError && finding.channel &&
        std::find(names.begin(), names.end(), *finding.channel) != names.end())
      finding.detail = WithoutFinalStop(finding.detail) + hint + ".";
}

// The sentence of the first error finding of `findings` (the test's failure).
std::string FirstErrorSentence(const std::vector<Finding>& findings) {
  const Finding* error = FirstError(findings);
  return error != nullptr ? WithoutFinalStop(error->detail) : std::string("screening found a faulty channel");
}

// The audit sentence of one salvaged channel (a warning finding).
Finding SalvageFinding(const SalvageAudit& record, const SalvagedChannel& channel) {
  std::ostringstream detail;
  detail << "salvage (" << record.mode << "): channel " << channel.channel << " ("
         << (channel.fault == FaultKind::kInconsistent ? "inconsistent with the other channels"
                                                       : std::string("a fault: ") + NameOf(channel.fault))
         << ", t = " << SalvageNumber(channel.t1_s, 6) << " s to " << SalvageNumber(channel.t2_s, 6)
         << " s) ";
  if (channel.action == SalvageAction::kExcluded)
    detail << "was left out; the result is solved from " << record.channels_used << " of "
           << record.channels_total << " channels";
  else if (channel.action == SalvageAction::kInverted)
    detail << "was inverted (its sign flipped back)";
  else if (channel.action == SalvageAction::kSwappedBack)
    detail << "was swapped back with channel " << channel.partner.value_or("?");
  else
    detail << "had " << channel.samples_replaced
           << " samples replaced by its rigid-body prediction from the other channels";
  detail << "; the RMS rigid-body residual ";
  if (std::isfinite(record.rms_residual_before_mps2))
    detail << "fell from " << SalvageNumber(record.rms_residual_before_mps2 / kStandardGravity) << " g";
  else
    detail << "is now";
  detail << " " << (std::isfinite(record.rms_residual_before_mps2) ? "to " : "")
         << SalvageNumber(record.rms_residual_after_mps2 / kStandardGravity, 3) << " g.";
  return Finding{NameOf(Check::kSalvage), channel.channel, Severity::kWarning, detail.str()};
}

// Salvage of a test whose screening named `faults` (config.screening.salvage
// is exclude or repair): the salvaged signals processed into `out` with the
// record of what was done. A second round takes the faults the first
// salvaged result shows (up to kMaxSalvagedChannels in all); a repair that
// leaves a channel faulty falls back to leaving it out. Throws
// ScreeningFailure with a sentence saying why when the test cannot be saved.
void Salvage(const ArrayGeometry& array, const TestSignals& raw_signals, const InitialState& initial,
             const ProcessingConfig& config, std::vector<FaultyChannel> faults, std::vector<Finding> findings,
             Workspace& workspace, ProcessedTest& out, const std::atomic<bool>* cancel,
             bool summary_series_only) {
  const double rms_before = workspace.exact_rms_residual_mps2;
  bool repair = config.screening.salvage == SalvageMode::kRepair;
  SalvageAudit record;
  record.mode = NameOf(config.screening.salvage);
  record.channels_total = static_cast<int>(array.sensors.size());
  const double shift_s = config.time.shift_s;
  TestSignals salvaged;
  for (int round = 0;; ++round) {
    const std::vector<std::string> names = FaultyChannelNames(faults);
    const std::string list = ChannelList(names);
    if (std::optional<std::string> impossible = SalvageImpossible(array, names)) {
      const std::string sentence = FirstErrorSentence(findings) + *impossible + ".";
      throw ScreeningFailure(sentence, std::move(findings));
    }
    std::string why;
    const std::optional<ArrayGeometry> reduced = ArrayWithout(array, names, why);
    const std::vector<FaultAnalysis> analyses =
        AnalyseFaults(array, *reduced, names, raw_signals, initial, config);
    ThrowIfCancelled(cancel);
    salvaged = raw_signals;
    record.channels.clear();
    for (std::size_t i = 0; i < names.size(); ++i) {
      const FaultAnalysis& analysis = analyses[i];
      const auto fault = std::find_if(faults.begin(), faults.end(), [&](const FaultyChannel& f) {
        return f.channel == names[i] || f.partner == names[i];
      });
      SalvagedChannel channel;
      channel.channel = names[i];
      // A flat top the raw saturation check calls clipped may be a stuck
      // reading: the samples against the prediction tell.
      channel.fault = fault->check == Check::kSaturation && analysis.kind == FaultKind::kStuck
                          ? FaultKind::kStuck
                          : KindOfCheck(fault->check).value_or(analysis.kind);
      const Eigen::Index first = analysis.first >= 0 ? analysis.first : 0;
      const Eigen::Index last = analysis.last >= 0 ? analysis.last : raw_signals.size() - 1;
      channel.t1_s = raw_signals.TimeAt(first) - shift_s;
      channel.t2_s = raw_signals.TimeAt(last) - shift_s;
      const int column = salvaged.FindSlot(names[i]);
      auto samples = salvaged.samples.col(column);
      if (!repair) {
        channel.action = SalvageAction::kExcluded;
        for (Eigen::Index k = 0; k < samples.size(); ++k)
          if (!std::isfinite(samples(k))) samples(k) = 0.0;  // unread: conditioning needs finite samples
      } else if (channel.fault == FaultKind::kFlipped) {
        channel.action = SalvageAction::kInverted;
        samples *= -1.0;
      } else if (channel.fault == FaultKind::kSwapped) {
        channel.action = SalvageAction::kSwappedBack;
        channel.partner =
            fault->channel == names[i] ? fault->partner : std::optional<std::string>(fault->channel);
        // Each column takes the other's recorded samples (in its own unit).
        const int other = raw_signals.FindSlot(channel.partner.value_or(""));
        const std::optional<std::size_t> sensor = array.FindSlot(names[i]);
        const std::optional<std::size_t> other_sensor = array.FindSlot(channel.partner.value_or(""));
        if (other >= 0 && sensor && other_sensor)
          samples = raw_signals.samples.col(other) *
                    (array.sensors[*other_sensor].si_per_unit / array.sensors[*sensor].si_per_unit);
      } else {
        channel.action = SalvageAction::kReplaced;
        for (const Eigen::Index k : analysis.samples) samples(k) = analysis.predicted(k);
        channel.samples_replaced = static_cast<std::int64_t>(analysis.samples.size());
      }
      record.channels.push_back(std::move(channel));
    }
    record.channels_used = static_cast<int>(repair ? array.sensors.size() : reduced->sensors.size());
    std::vector<FaultyChannel> more;
    try {
      ProcessOnce(repair ? array : *reduced, salvaged, initial, config, workspace, out, cancel,
                  summary_series_only);
      more = SalvageableFaults(out.summary.findings);
    } catch (const ScreeningFailure& failure) {
      more = SalvageableFaults(failure.findings());
      findings = failure.findings();
      const bool known = std::all_of(more.begin(), more.end(), [&names](const FaultyChannel& f) {
        return std::find(names.begin(), names.end(), f.channel) != names.end();
      });
      if (more.empty() || round > 1 || (known && !repair))
        throw ScreeningFailure(
            "salvage (" + record.mode + ") of " + list + " did not recover the test: " + failure.what(),
            failure.findings());
    }
    if (more.empty()) break;
    const bool same = std::all_of(more.begin(), more.end(), [&names](const FaultyChannel& f) {
      return std::find(names.begin(), names.end(), f.channel) != names.end();
    });
    if (same && repair) {
      repair = false;  // the repair left a channel off the rigid body: leave the channels out instead
    } else if (same || round > 1) {
      break;  // the result fails with its finding (FailingFinding)
    } else {
      for (FaultyChannel& fault : more)
        if (std::find(names.begin(), names.end(), fault.channel) == names.end()) faults.push_back(fault);
    }
    findings = out.summary.findings;
  }
  record.rms_residual_before_mps2 = rms_before;
  record.rms_residual_after_mps2 = workspace.exact_rms_residual_mps2;
  for (const SalvagedChannel& channel : record.channels)
    out.summary.findings.push_back(SalvageFinding(record, channel));
  // The repaired channels are kept with the record (stored beside the
  // recorded ones, docs/formats.md "Salvage record").
  if (repair)
    for (SalvagedChannel& channel : record.channels) {
      const auto column = salvaged.samples.col(salvaged.FindSlot(channel.channel));
      channel.repaired_samples.assign(column.begin(), column.end());
    }
  out.summary.salvage = std::move(record);
}
}  // namespace

ProcessedTest ProcessTest(const ArrayGeometry& array, const TestSignals& raw_signals,
                          const InitialState& initial, const ProcessingConfig& config,
                          const std::atomic<bool>* cancel) {
  Workspace workspace;
  ProcessedTest processed;
  ProcessTest(array, raw_signals, initial, config, workspace, processed, cancel, SeriesKept::kAll);
  return processed;
}

void ProcessTest(const ArrayGeometry& array, const TestSignals& raw_signals, const InitialState& initial,
                 const ProcessingConfig& config, Workspace& workspace, ProcessedTest& out,
                 const std::atomic<bool>* cancel, SeriesKept series) {
  config.Check();
  const bool salvage = config.screening.salvage != SalvageMode::kOff;
  const bool summary_series_only = series == SeriesKept::kSummary;
  try {
    ProcessOnce(array, raw_signals, initial, config, workspace, out, cancel, summary_series_only);
  } catch (const ScreeningFailure& failure) {
    std::vector<FaultyChannel> faults = SalvageableFaults(failure.findings());
    ResolveConfounded(array, raw_signals, initial, config, failure.findings(), faults);
    if (faults.empty()) throw;
    if (!salvage) {
      const std::string hint = SalvageHint(array, faults);
      std::vector<Finding> findings = failure.findings();
      AddSalvageHint(findings, faults, hint);
      throw ScreeningFailure(WithoutFinalStop(failure.what()) + hint + ".", std::move(findings));
    }
    Salvage(array, raw_signals, initial, config, faults, failure.findings(), workspace, out, cancel,
            summary_series_only);
    return;
  }
  std::vector<FaultyChannel> faults = SalvageableFaults(out.summary.findings);
  ResolveConfounded(array, raw_signals, initial, config, out.summary.findings, faults);
  if (faults.empty()) return;
  if (!salvage) {
    AddSalvageHint(out.summary.findings, faults, SalvageHint(array, faults));
    return;
  }
  Salvage(array, raw_signals, initial, config, faults, out.summary.findings, workspace, out, cancel,
          summary_series_only);
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
  // max(padding_s, 1 / CFC) at both ends and runs up to twelve channels
  // abreast (CfcFilter::ApplyInPlaceToColumns).
  double filtering = 0.0;
  const auto filter_columns = [&](std::size_t count, const std::optional<double>& cfc) {
    if (count == 0 || !cfc || !(dt_s > 0.0)) return 0.0;
    const double pad = std::min(std::ceil(std::max(config.filter.padding_s, 1.0 / *cfc) / dt_s), n - 1.0);
    return 12.0 * (n + 2.0 * pad) / n;
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
