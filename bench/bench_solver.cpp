// Solver throughput on a 20,000-sample NAP test (2 s at 10 kHz of random
// head motion, Denton 3-2-2-2 with displaced sensors): napkin's exact solver
// (solve + orientation + fixed-frame series + angles, no filtering) and the
// seed solver (LC_COMP of report Appendix B) on the same record, and the
// ratio of their rates. This file holds napkin_bench's main(): it runs every
// registered benchmark as Google Benchmark's own main would, then prints
//   exact/seed samples/s ratio: X
// from the best repetition of each solver benchmark of this run (e.g.
// `napkin_bench --benchmark_filter=SolverNap --benchmark_repetitions=5`).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "engine/pipeline.h"
#include "engine/solver.h"
#include "engine/units.h"
#include "synth/synthetic_tests.h"

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

// The record both solvers process: 20,000 samples of the displaced Denton array.
const synth::SyntheticTest& NapTest20000() {
  static const synth::SyntheticTest kTest = [] {
    synth::RandomMotionOptions motion;
    motion.seed = 1;
    motion.duration_s = 1.9999;  // 20,000 samples at 10 kHz
    return synth::SynthRandomMotion(synth::DisplaceSensors(DentonNap(), 0.25 * kMetresPerInch, 1), motion);
  }();
  return kTest;
}

void SolveNap20000(benchmark::State& state, SolverKind solver) {
  const synth::SyntheticTest& test = NapTest20000();
  SolveOptions options;
  options.solver = solver;
  options.initial = test.initial;
  // Kept from test to test, as a loop over tests does (engine/solver.h): the
  // solve maps no new pages, whatever glibc's malloc thresholds.
  Kinematics kinematics;
  for (auto _ : state) {
    Solve(test.array, test.signals, options, kinematics);
    benchmark::DoNotOptimize(kinematics.omega_body.data());
    benchmark::DoNotOptimize(kinematics.roll_pitch_yaw_rad.data());
  }
  state.SetItemsProcessed(state.iterations() * test.signals.size());
  state.counters["samples"] = static_cast<double>(test.signals.size());
  state.counters["samples_per_s"] = benchmark::Counter(static_cast<double>(test.signals.size()),
                                                       benchmark::Counter::kIsIterationInvariantRate);
}

void BM_ExactSolverNap20000(benchmark::State& state) { SolveNap20000(state, SolverKind::kExact); }
BENCHMARK(BM_ExactSolverNap20000)->Unit(benchmark::kMillisecond);

void BM_SeedSolverNap20000(benchmark::State& state) { SolveNap20000(state, SolverKind::kSeed); }
BENCHMARK(BM_SeedSolverNap20000)->Unit(benchmark::kMillisecond);

// The whole transform core (engine::ProcessTest: screening, conditioning,
// CFC filters, exact solver, consistency and plausibility screening,
// summary, HIC/a3ms/BrIC/DAMAGE) of the same record under the default
// processing config, test after test in one workspace (engine/pipeline.h),
// as `napkin run`'s compute threads and the Python module do.
void BM_ProcessTestNap20000(benchmark::State& state) {
  const synth::SyntheticTest& test = NapTest20000();
  const ProcessingConfig config;
  Workspace workspace;
  ProcessedTest processed;
  for (auto _ : state) {
    ProcessTest(test.array, test.signals, test.initial, config, workspace, processed);
    benchmark::DoNotOptimize(processed.kinematics.omega_body.data());
  }
  state.SetItemsProcessed(state.iterations() * test.signals.size());
  state.counters["samples_per_s"] = benchmark::Counter(static_cast<double>(test.signals.size()),
                                                       benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_ProcessTestNap20000)->Unit(benchmark::kMillisecond);

// The console reporter, also keeping the best samples/s of each benchmark
// over its repetitions (or, with --benchmark_display_aggregates_only, the
// median aggregate, the only rate it is given).
class RateCapturingReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& run : runs) {
      if (run.error_occurred) continue;
      const auto counter = run.counters.find("samples_per_s");
      if (counter == run.counters.end()) continue;
      const auto rate = static_cast<double>(counter->second);
      if (run.run_type == Run::RT_Iteration) {
        double& best = best_rate_[run.run_name.function_name];
        best = std::max(best, rate);
      } else if (run.aggregate_name == "median") {
        median_rate_[run.run_name.function_name] = rate;
      }
    }
    ConsoleReporter::ReportRuns(runs);
  }

  // Best samples/s of `name` (else its median), 0 when it did not run.
  double BestRate(const std::string& name) const {
    for (const auto* rates : {&best_rate_, &median_rate_}) {
      const auto found = rates->find(name);
      if (found != rates->end()) return found->second;
    }
    return 0.0;
  }

 private:
  std::map<std::string, double> best_rate_, median_rate_;
};

}  // namespace
}  // namespace napkin::engine

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  napkin::engine::RateCapturingReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  const double exact = reporter.BestRate("BM_ExactSolverNap20000");
  const double seed = reporter.BestRate("BM_SeedSolverNap20000");
  if (exact > 0.0 && seed > 0.0) {
    std::printf(
        "exact solver: %.3f M samples/s, seed solver: %.3f M samples/s (best repetition, else median)\n",
        exact / 1e6, seed / 1e6);
    std::printf("exact/seed samples/s ratio: %.3f\n", exact / seed);
  } else if (exact > 0.0) {
    // The exact solver alone (bench/run_solver_scale.sh).
    std::printf("exact solver: %.3f M samples/s (best repetition, else median)\n", exact / 1e6);
  }
  benchmark::Shutdown();
  return 0;
}
