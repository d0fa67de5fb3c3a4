#include "engine/solver.h"

#include <cmath>
#include <sstream>

#include "common/error.h"
#include "engine/exact_solver.h"
#include "engine/seed_solver.h"

namespace napkin::engine {
namespace {

// Every channel the array needs is present, finite and uniformly sampled.
void CheckSignals(const ArrayGeometry& array, const TestSignals& signals) {
  if (!std::isfinite(signals.dt_s) || signals.dt_s <= 0.0) {
    std::ostringstream message;
    message << "the sampling interval must be positive and finite (got dt = " << signals.dt_s << " s).";
    throw InputError(message.str());
  }
  if (!std::isfinite(signals.t0_s)) throw InputError("the time of the first sample is not finite.");
  if (signals.samples.cols() != static_cast<Eigen::Index>(signals.slots.size()))
    throw InputError("the signals have " + std::to_string(signals.samples.cols()) + " columns but " +
                     std::to_string(signals.slots.size()) + " channel names.");
  if (signals.size() < 2)
    throw InputError("the signals have " + std::to_string(signals.size()) +
                     " sample(s); at least 2 are needed to integrate.");
  for (const Sensor& sensor : array.sensors) {
    const int column = signals.FindSlot(sensor.slot);
    if (column < 0)
      throw InputError("channel '" + sensor.slot + "' required by array '" + array.name + "' is missing.");
    const auto values = signals.samples.col(column);
    // x * 0 is +-0 for finite x and NaN for an infinity or NaN, and a sum of
    // zeros stays 0 while one NaN makes it NaN: one vectorized pass checks the
    // channel (a per-sample test cost 3 % of the exact solve, perf); the row
    // is only looked for when there is one.
    if (!std::isnan((values.array() * 0.0).sum())) continue;
    for (Eigen::Index k = 0; k < values.size(); ++k) {
      if (!std::isfinite(values(k))) {
        std::ostringstream message;
        message << "channel '" << sensor.slot << "' has a non-finite value at row " << k + 1
                << " (t = " << signals.TimeAt(k) << " s).";
        throw InputError(message.str());
      }
    }
  }
}

}  // namespace

Kinematics Solve(const ArrayGeometry& array, const TestSignals& signals, const SolveOptions& options) {
  Kinematics kinematics;
  Solve(array, signals, options, kinematics);
  return kinematics;
}

void Solve(const ArrayGeometry& array, const TestSignals& signals, const SolveOptions& options,
           Kinematics& out) {
  ArrayGeometry validated = array;
  ValidateArray(validated);
  CheckSignals(validated, signals);
  if (options.body_frame_only && (options.solver == SolverKind::kSeed || options.gravity.compensate))
    throw InputError(
        "a body-frame-only solve needs the exact solver without gravity compensation (the gravity term needs "
        "the orientation).");
  if (options.solver == SolverKind::kSeed) {
    // Refused rather than ignored (ProcessingConfig::Check says the same).
    if (options.gravity.compensate)
      throw InputError(
          "gravity compensation is not supported by the seed solver (LC_COMP has no gravity term).");
    if (options.corrector_passes != kDefaultCorrectorPasses)
      throw InputError(
          "corrector_passes is not supported by the seed solver (LC_COMP integrates in one pass).");
    out = SolveSeed(validated, signals, options.initial, options.cancel);
    return;
  }
  if (options.corrector_passes < 1)
    throw InputError("corrector_passes must be at least 1 (got " + std::to_string(options.corrector_passes) +
                     ").");
  SolveExact(validated, signals, options, out);
}

}  // namespace napkin::engine
