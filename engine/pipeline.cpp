#include "engine/pipeline.h"

#include <algorithm>

#include "engine/criteria.h"
#include "engine/error.h"
#include "engine/screening.h"
#include "engine/solver.h"

namespace napkin::engine {

ProcessedTest ProcessTest(const ArrayGeometry& array, const TestSignals& raw_signals, const InitialState& initial,
                          const ProcessingConfig& config) {
  config.Check();
  // Screening runs on the raw signals first (report section 2.2: check the
  // data before using them). A missing channel or a non-finite sample makes
  // the test unusable: stop with the finding's sentence (slot, sample, time).
  std::vector<Finding> findings = ScreenSignals(array, raw_signals, initial, config);
  const auto fatal = std::find_if(findings.begin(), findings.end(), IsFatal);
  if (fatal != findings.end()) throw InputError(fatal->detail);

  TestSignals signals = raw_signals;
  ApplyConditioning(array, signals, config);
  ProcessedTest processed;
  const SolveOptions options = MakeSolveOptions(config, initial);
  processed.kinematics = Solve(array, signals, options);
  SummarizeKinematics(processed.kinematics, processed.summary);
  FillCriteria(processed.kinematics, config, processed.summary);

  // Rigid-body consistency is judged by the exact solver's residual, also
  // when the result comes from the seed solver.
  std::vector<Finding> consistency;
  if (options.solver == SolverKind::kExact) {
    consistency = ScreenConsistency(array, signals, processed.kinematics, options, config.screening);
  } else {
    SolveOptions exact_options = options;
    exact_options.solver = SolverKind::kExact;
    consistency = ScreenConsistency(array, signals, Solve(array, signals, exact_options), exact_options,
                                    config.screening);
  }
  findings.insert(findings.end(), consistency.begin(), consistency.end());
  processed.summary.findings = std::move(findings);
  return processed;
}

}  // namespace napkin::engine
