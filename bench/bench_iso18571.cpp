// ISO/TS 18571 ratings of 10,000-sample curve pairs (1 s at the standard's
// 10 kHz): a model that follows the test, with measurement noise on both
// (flat noisy stretches: the pruned warping keeps most of the band) and
// without (few cells per row), and an unrelated curve (the whole band of the
// 2024 edition's 10 % window).
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "engine/cfc_filter.h"
#include "engine/iso18571.h"

namespace napkin::engine {
namespace {

constexpr double kIsoDt = 1e-4;  // 10 kHz
constexpr Eigen::Index kIsoSamples = 10000;

// Haversine pulses (start s, length s, height) plus noise, filtered at CFC 1000.
Eigen::VectorXd IsoCrashCurve(std::uint64_t seed, double delay_s, double scale, double noise_sd = 1.0) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_sd);
  Eigen::VectorXd a(kIsoSamples);
  const auto haversine = [](double t, double start, double length, double height) {
    const double s = (t - start) / length;
    return s >= 0.0 && s <= 1.0 ? height * 0.5 * (1.0 - std::cos(2.0 * std::numbers::pi * s)) : 0.0;
  };
  for (Eigen::Index k = 0; k < kIsoSamples; ++k) {
    const double t = static_cast<double>(k) * kIsoDt - delay_s;
    a[k] = scale * (haversine(t, 0.10, 0.014, 85.0) + haversine(t, 0.13, 0.030, 38.0) +
                    haversine(t, 0.40, 0.040, 12.0)) +
           noise(rng);
  }
  CfcFilterInPlace(a, kIsoDt, kCfc1000);
  // The filter's tails decay into subnormal numbers, whose arithmetic is
  // slow on any code; a recorded or simulated curve has none.
  for (Eigen::Index k = 0; k < kIsoSamples; ++k)
    if (std::abs(a[k]) < 1e-12) a[k] = 0.0;
  return a;
}

void RatePairs(benchmark::State& state, const Eigen::VectorXd& reference, const Eigen::VectorXd& candidate,
               Iso18571Edition edition) {
  const Iso18571Parameters parameters = Iso18571Parameters::ForEdition(edition);
  const std::span<const double> t(reference.data(), static_cast<std::size_t>(reference.size()));
  const std::span<const double> c(candidate.data(), static_cast<std::size_t>(candidate.size()));
  for (auto _ : state) benchmark::DoNotOptimize(Iso18571Rate(t, c, kIsoDt, parameters));
  state.SetItemsProcessed(state.iterations());  // pairs: items/s = pairs per second
}

// The model: 5 % larger, 0.5 ms later, its own noise.
void BM_Iso18571_ModelPair10k(benchmark::State& state) {
  static const Eigen::VectorXd kTest = IsoCrashCurve(1, 0.0, 1.0);
  static const Eigen::VectorXd kModel = IsoCrashCurve(2, 0.0005, 1.05);
  RatePairs(state, kTest, kModel, Iso18571Edition::k2024);
}
BENCHMARK(BM_Iso18571_ModelPair10k)->Unit(benchmark::kMillisecond);

// Both noise-free (a synthetic test's truth against a model): the pruning
// keeps a few cells per row.
void BM_Iso18571_SmoothModelPair10k(benchmark::State& state) {
  static const Eigen::VectorXd kTest = IsoCrashCurve(1, 0.0, 1.0, 0.0);
  static const Eigen::VectorXd kModel = IsoCrashCurve(2, 0.0005, 1.05, 0.0);
  RatePairs(state, kTest, kModel, Iso18571Edition::k2024);
}
BENCHMARK(BM_Iso18571_SmoothModelPair10k)->Unit(benchmark::kMillisecond);

// An unrelated curve (pulses elsewhere): every cell of the 10 % band.
void BM_Iso18571_UnrelatedPair10k(benchmark::State& state) {
  static const Eigen::VectorXd kTest = IsoCrashCurve(1, 0.0, 1.0);
  static const Eigen::VectorXd kOther = IsoCrashCurve(3, 0.25, -0.6);
  RatePairs(state, kTest, kOther, Iso18571Edition::k2024);
}
BENCHMARK(BM_Iso18571_UnrelatedPair10k)->Unit(benchmark::kMillisecond);

// The 2014 edition warps without a window: the pruning alone bounds the work.
void BM_Iso18571_ModelPair10kEdition2014(benchmark::State& state) {
  static const Eigen::VectorXd kTest = IsoCrashCurve(1, 0.0, 1.0);
  static const Eigen::VectorXd kModel = IsoCrashCurve(2, 0.0005, 1.05);
  RatePairs(state, kTest, kModel, Iso18571Edition::k2014);
}
BENCHMARK(BM_Iso18571_ModelPair10kEdition2014)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace napkin::engine
