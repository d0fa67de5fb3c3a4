#pragma once
// The transform core: everything napkin does to one test, from raw signals
// to kinematics, criteria and screening findings. `napkin transform` and the
// batch scheduler (jobs/) both call ProcessTest, so a catalogue result equals
// the single-test result for the same input and configuration.
#include "engine/array_geometry.h"
#include "engine/kinematics.h"
#include "engine/processing.h"
#include "engine/signals.h"
#include "engine/summary.h"

namespace napkin::engine {

struct ProcessedTest {
  Kinematics kinematics;
  TestSummary summary;
};

// Conditioning (time shift, bias, CFC filters, crop) -> solver -> summary ->
// injury criteria -> screening. Throws InputError naming the slot, row or
// setting at fault.
ProcessedTest ProcessTest(const ArrayGeometry& array, const TestSignals& raw_signals, const InitialState& initial,
                          const ProcessingConfig& config);

}  // namespace napkin::engine
