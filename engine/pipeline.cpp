#include "engine/pipeline.h"

#include "engine/criteria.h"
#include "engine/solver.h"

namespace napkin::engine {

ProcessedTest ProcessTest(const ArrayGeometry& array, const TestSignals& raw_signals, const InitialState& initial,
                          const ProcessingConfig& config) {
  config.Check();
  TestSignals signals = raw_signals;
  ApplyConditioning(array, signals, config);
  ProcessedTest processed;
  processed.kinematics = Solve(array, signals, MakeSolveOptions(config, initial));
  SummarizeKinematics(processed.kinematics, processed.summary);
  FillCriteria(processed.kinematics, config, processed.summary);
  return processed;
}

}  // namespace napkin::engine
