// Exact-solver throughput on a 20,000-sample NAP test (2 s at 10 kHz of
// random head motion, Denton 3-2-2-2 with displaced sensors).
#include <benchmark/benchmark.h>

#include "engine/solver.h"
#include "engine/synth.h"
#include "engine/units.h"

namespace napkin::engine {
namespace {

ArrayGeometry DentonNap() {
  // Appendix A Denton 3-2-2-2 positions (in), Table 2-1 axes.
  const double positions_in[9][3] = {{0.203, 0, 0},   {0, 0.203, 0},   {0, 0, 0.203},
                                     {0, 1.9, 0.203}, {0.203, 1.9, 0}, {2.2, 0, 0.203},
                                     {2.2, 0.203, 0}, {0.203, 0, 3.2}, {0, 0.203, 3.2}};
  const int axes[9] = {0, 1, 2, 2, 0, 2, 1, 0, 1};
  ArrayGeometry array;
  array.name = "denton-3222";
  for (int i = 0; i < 9; ++i) {
    Sensor sensor;
    sensor.slot = kNapSlots[i];
    sensor.position_body_m =
        Eigen::Vector3d(positions_in[i][0], positions_in[i][1], positions_in[i][2]) * kMetresPerInch;
    sensor.axis_body = Eigen::Vector3d::Unit(axes[i]);
    array.sensors.push_back(sensor);
  }
  return array;
}

void BM_ExactSolverNap20000(benchmark::State& state) {
  RandomMotionOptions motion;
  motion.seed = 1;
  motion.duration_s = 1.9999;  // 20,000 samples at 10 kHz
  const SyntheticTest test =
      SynthRandomMotion(DisplaceSensors(DentonNap(), 0.25 * kMetresPerInch, 1), motion);
  SolveOptions options;
  options.initial = test.initial;
  for (auto _ : state) {
    Kinematics kinematics = Solve(test.array, test.signals, options);
    benchmark::DoNotOptimize(kinematics.omega_body.data());
  }
  state.SetItemsProcessed(state.iterations() * test.signals.size());
  state.counters["samples"] = static_cast<double>(test.signals.size());
  state.counters["samples_per_s"] = benchmark::Counter(static_cast<double>(test.signals.size()),
                                                       benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_ExactSolverNap20000)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace napkin::engine
