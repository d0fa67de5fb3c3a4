// HIC (fast branch and bound vs exhaustive) and CFC filter throughput.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "engine/cfc_filter.h"
#include "engine/criteria.h"
#include "engine/units.h"

namespace napkin::engine {
namespace {

constexpr double kDt = 1e-4;   // 10 kHz
constexpr double kT0 = -0.05;  // 50 ms pre-impact
constexpr Eigen::Index kSamples = 20000;

// A crash-like resultant head acceleration (g): a primary impact, a
// secondary contact and a rebound, broadband noise, filtered at CFC 1000.
const Eigen::VectorXd& CrashLikeSignal() {
  static const Eigen::VectorXd kSignal = [] {
    std::mt19937_64 rng(1995);
    std::normal_distribution<double> noise(0.0, 1.5);
    Eigen::VectorXd a(kSamples);
    const auto haversine = [](double t, double start, double length, double height) {
      const double s = (t - start) / length;
      return s >= 0.0 && s <= 1.0 ? height * 0.5 * (1.0 - std::cos(2.0 * std::numbers::pi * s)) : 0.0;
    };
    for (Eigen::Index k = 0; k < kSamples; ++k) {
      const double t = kT0 + static_cast<double>(k) * kDt;
      a[k] = haversine(t, 0.010, 0.014, 85.0) + haversine(t, 0.030, 0.030, 38.0) +
             haversine(t, 0.075, 0.040, 12.0) + noise(rng);
    }
    CfcFilterInPlace(a, kDt, kCfc1000);
    return Eigen::VectorXd(a.cwiseAbs());  // a resultant is non-negative
  }();
  return kSignal;
}

HicOptions WindowOf(double window_s) {
  HicOptions options;
  options.window_s = window_s;
  return options;
}

void BM_HicFast(benchmark::State& state, double window_s) {
  const Eigen::VectorXd& a = CrashLikeSignal();
  for (auto _ : state) benchmark::DoNotOptimize(Hic(a, kDt, kT0, WindowOf(window_s)));
  state.SetItemsProcessed(state.iterations() * kSamples);
}

void BM_HicExhaustive(benchmark::State& state, double window_s) {
  const Eigen::VectorXd& a = CrashLikeSignal();
  for (auto _ : state) benchmark::DoNotOptimize(HicExhaustive(a, kDt, kT0, WindowOf(window_s)));
  state.SetItemsProcessed(state.iterations() * kSamples);
}

BENCHMARK_CAPTURE(BM_HicFast, unlimited, kUnlimitedHicWindow)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_HicExhaustive, unlimited, kUnlimitedHicWindow)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(2);
BENCHMARK_CAPTURE(BM_HicFast, hic36, kHic36Window)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_HicExhaustive, hic36, kHic36Window)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_HicFast, hic15, kHic15Window)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_HicExhaustive, hic15, kHic15Window)->Unit(benchmark::kMillisecond);

// HIC15, HIC36 and the unlimited HIC of one signal, as a summary needs
// them: one call (shared integral and tree, seeded searches).
void BM_HicThreeWindows(benchmark::State& state) {
  const Eigen::VectorXd& a = CrashLikeSignal();
  const std::vector<double> windows{kHic15Window, kHic36Window, kUnlimitedHicWindow};
  for (auto _ : state) benchmark::DoNotOptimize(HicForWindows(a, kDt, kT0, windows));
  state.SetItemsProcessed(state.iterations() * kSamples);
}
BENCHMARK(BM_HicThreeWindows)->Unit(benchmark::kMillisecond);

// Both searches on the same signal: checks they agree and reports the
// speed-up of the fast one as a counter.
void BM_HicUnlimitedSpeedup(benchmark::State& state) {
  const Eigen::VectorXd& a = CrashLikeSignal();
  using Clock = std::chrono::steady_clock;
  for (auto _ : state) {
    const auto start = Clock::now();
    const HicWindow exhaustive = HicExhaustive(a, kDt, kT0);
    const auto middle = Clock::now();
    constexpr int kFastRuns = 20;
    HicWindow fast;
    for (int run = 0; run < kFastRuns; ++run) fast = Hic(a, kDt, kT0);
    const auto end = Clock::now();
    if (fast.value != exhaustive.value || fast.t1_s != exhaustive.t1_s || fast.t2_s != exhaustive.t2_s) {
      state.SkipWithError("fast HIC differs from the exhaustive search");
      return;
    }
    const double exhaustive_s = std::chrono::duration<double>(middle - start).count();
    const double fast_s = std::chrono::duration<double>(end - middle).count() / kFastRuns;
    state.counters["hic"] = fast.value;
    state.counters["t1_ms"] = fast.t1_s * 1e3;
    state.counters["t2_ms"] = fast.t2_s * 1e3;
    state.counters["exhaustive_ms"] = exhaustive_s * 1e3;
    state.counters["fast_ms"] = fast_s * 1e3;
    state.counters["speedup"] = exhaustive_s / fast_s;
  }
}
BENCHMARK(BM_HicUnlimitedSpeedup)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_CfcFilter(benchmark::State& state) {
  const Eigen::VectorXd& a = CrashLikeSignal();
  Eigen::VectorXd out(a.size());
  CfcFilter filter(kCfc1000, kDt);
  for (auto _ : state) {
    filter.Apply(a, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * a.size());
  state.SetBytesProcessed(state.iterations() * a.size() * static_cast<std::int64_t>(sizeof(double)));
}
BENCHMARK(BM_CfcFilter)->Unit(benchmark::kMicrosecond);

// The nine channels of a NAP test, one at a time and together
// (CfcFilter::ApplyInPlaceToColumns).
void BM_CfcFilterNineChannels(benchmark::State& state, bool together) {
  const Eigen::VectorXd& a = CrashLikeSignal();
  Eigen::MatrixXd channels(a.size(), 9);
  for (Eigen::Index c = 0; c < 9; ++c) channels.col(c) = a * (1.0 + 0.1 * static_cast<double>(c));
  const std::vector<Eigen::Index> columns{0, 1, 2, 3, 4, 5, 6, 7, 8};
  CfcFilter filter(kCfc1000, kDt);
  for (auto _ : state) {
    Eigen::MatrixXd work = channels;
    if (together) {
      filter.ApplyInPlaceToColumns(work, columns);
    } else {
      for (const Eigen::Index c : columns) filter.ApplyInPlace(work.col(c));
    }
    benchmark::DoNotOptimize(work.data());
  }
  state.SetItemsProcessed(state.iterations() * a.size() * 9);
}
BENCHMARK_CAPTURE(BM_CfcFilterNineChannels, one_at_a_time, false)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_CfcFilterNineChannels, together, true)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace napkin::engine
