#include "engine/cfc_filter.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numbers>
#include <sstream>

#include "common/error.h"
#include "engine/cancellation.h"
#include "engine/units.h"

namespace napkin::engine {

namespace {

// omega_a = tan(omega_d T / 2): the pre-warped analogue cut-off of one pass.
double PrewarpedCutoff(double cfc_hz, double dt_s, CfcVariant variant) {
  if (!(std::isfinite(cfc_hz) && cfc_hz > 0.0)) {
    std::ostringstream message;
    message << "the CFC filter class " << cfc_hz << " Hz is not a positive frequency.";
    throw InputError(message.str());
  }
  if (!(std::isfinite(dt_s) && dt_s > 0.0)) {
    std::ostringstream message;
    message << "the sampling interval " << dt_s << " s given to the CFC filter is not positive.";
    throw InputError(message.str());
  }
  const double half_angle = 2.0 * std::numbers::pi * cfc_hz * CfcDesignFactor(variant) * dt_s / 2.0;
  if (half_angle >= 0.5 * std::numbers::pi * (1.0 - 1e-9)) {
    std::ostringstream message;
    message << "CFC " << cfc_hz << " cannot be applied at a sampling rate of " << 1.0 / dt_s
            << " Hz (the design frequency reaches Nyquist; sample faster or choose a lower class).";
    throw InputError(message.str());
  }
  return std::tan(half_angle);
}

// One pass of the recursion over w[begin..end) in the given direction
// (step = +1 forward, -1 backward), in place, starting in the steady state of
// the first value (x[t-1] = x[t-2] = y[t-1] = y[t-2] = first value; the DC
// gain is exactly 1, see ComputeCfcCoefficients).
void RunPass(const CfcCoefficients& c, double* w, Eigen::Index n, bool forward) {
  Eigen::Index k = forward ? 0 : n - 1;
  const Eigen::Index step = forward ? 1 : -1;
  const double first = w[k];
  double x1 = first, x2 = first, y1 = first, y2 = first;
  for (Eigen::Index count = 0; count < n; ++count, k += step) {
    const double x = w[k];
    const double y = c.a0 * x + c.a1 * x1 + c.a2 * x2 + c.b1 * y1 + c.b2 * y2;
    w[k] = y;
    x2 = x1;
    x1 = x;
    y2 = y1;
    y1 = y;
  }
}

// RunPass on kVectors * 4 channels stored interleaved (w[k * lanes + lane]),
// each with RunPass's operations in RunPass's order: the lanes of a GCC
// vector are computed element-wise with IEEE arithmetic, as the scalars
// would be (no FMA contraction: -std=c++20 and engine/CMakeLists.txt), so
// every build and clone gives RunPass's bits. All the vectors of a step are
// independent chains: with the nine channels of an array in one group of
// three vectors, the processor overlaps their multiply-adds where groups of
// four channels one after the other each waited on their own chain. Four-lane
// vectors are two SSE2 registers in the default clone and one AVX register in
// the AVX2 clone (NAPKIN_FILTER_LOOP_CLONES); they never cross a function
// boundary (no ABI surprises). Coefficients and state live in locals
// (registers), not behind pointers the stores to w could alias.
using LaneVector = double __attribute__((vector_size(4 * sizeof(double))));
constexpr Eigen::Index kLanesPerVector = 4;
// At most this many vectors (12 channels) abreast: nine or ten channels in one
// group, and the state (four vectors per chain) still fits the registers.
constexpr int kMaxVectors = 3;

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define NAPKIN_FILTER_LOOP_CLONES __attribute__((target_clones("default", "avx2")))
#else
#define NAPKIN_FILTER_LOOP_CLONES
#endif

// The recursion's state of one vector of channels. Separate variables per
// vector (no array of vectors), so that the compiler keeps them in registers.
struct LaneState {
  LaneVector x1, x2, y1, y2;
};

struct LaneCoefficients {
  LaneVector a0, a1, a2, b1, b2;
};

inline __attribute__((always_inline)) void StartLanes(const double* row, LaneState& state) {
  LaneVector first;
  std::memcpy(&first, row, sizeof first);
  state.x1 = state.x2 = state.y1 = state.y2 = first;
}

// One step of RunPass on one vector of channels, in place at `row`.
inline __attribute__((always_inline)) void StepLanes(const LaneCoefficients& c, double* row,
                                                     LaneState& state) {
  LaneVector x;
  std::memcpy(&x, row, sizeof x);
  const LaneVector y = c.a0 * x + c.a1 * state.x1 + c.a2 * state.x2 + c.b1 * state.y1 + c.b2 * state.y2;
  std::memcpy(row, &y, sizeof y);
  state.x2 = state.x1;
  state.x1 = x;
  state.y2 = state.y1;
  state.y1 = y;
}

template <int kVectors>
// False when `cancel` stopped it. It never throws: the caller does (IsCancelled says why).
NAPKIN_FILTER_LOOP_CLONES bool RunPassInterleaved(const CfcCoefficients& c, double* w, Eigen::Index n,
                                                  bool forward, const std::atomic<bool>* cancel) {
  static_assert(kVectors >= 1 && kVectors <= kMaxVectors);
  constexpr Eigen::Index kLanes = kVectors * kLanesPerVector;
  const LaneCoefficients lane_c = {{c.a0, c.a0, c.a0, c.a0},
                                   {c.a1, c.a1, c.a1, c.a1},
                                   {c.a2, c.a2, c.a2, c.a2},
                                   {c.b1, c.b1, c.b1, c.b1},
                                   {c.b2, c.b2, c.b2, c.b2}};
  Eigen::Index k = forward ? 0 : n - 1;
  const Eigen::Index step = forward ? 1 : -1;
  LaneState state0, state1, state2;
  StartLanes(w + k * kLanes, state0);
  if constexpr (kVectors > 1) StartLanes(w + k * kLanes + kLanesPerVector, state1);
  if constexpr (kVectors > 2) StartLanes(w + k * kLanes + 2 * kLanesPerVector, state2);
  for (Eigen::Index count = 0; count < n; ++count, k += step) {
    if (IsCancelled(cancel, count)) return false;
    double* row = w + k * kLanes;
    StepLanes(lane_c, row, state0);
    if constexpr (kVectors > 1) StepLanes(lane_c, row + kLanesPerVector, state1);
    if constexpr (kVectors > 2) StepLanes(lane_c, row + 2 * kLanesPerVector, state2);
  }
  return true;
}

// Both passes over `vectors` (1 .. kMaxVectors) vectors of interleaved channels.
void RunPassesInterleaved(const CfcCoefficients& c, double* w, Eigen::Index n, int vectors,
                          const std::atomic<bool>* cancel) {
  for (const bool forward : {true, false}) {
    const bool completed = vectors == 1   ? RunPassInterleaved<1>(c, w, n, forward, cancel)
                           : vectors == 2 ? RunPassInterleaved<2>(c, w, n, forward, cancel)
                                          : RunPassInterleaved<3>(c, w, n, forward, cancel);
    if (!completed) throw Cancelled();
  }
}

}  // namespace

namespace {
struct ClassCutoff {
  double cfc;
  double cutoff_hz;
};
constexpr ClassCutoff kJ211Cutoffs[] = {
    {kCfc60, 100.0}, {kCfc180, 300.0}, {kCfc600, 1000.0}, {kCfc1000, 1650.0}};
}  // namespace

std::optional<double> J211ClassOfCutoff(double cutoff_hz) {
  for (const ClassCutoff& entry : kJ211Cutoffs)
    if (std::abs(cutoff_hz - entry.cutoff_hz) <= kJ211CutoffTolerance * entry.cutoff_hz) return entry.cfc;
  return std::nullopt;
}

double J211CutoffOfClass(double cfc) {
  for (const ClassCutoff& entry : kJ211Cutoffs)
    if (std::abs(cfc - entry.cfc) <= 1e-9 * entry.cfc) return entry.cutoff_hz;
  return cfc * 5.0 / 3.0;
}

double CfcDesignFactor(CfcVariant variant) {
  switch (variant) {
    case CfcVariant::kSaeJ211:
      return 2.0775;
    case CfcVariant::kIso6487:
      return 25.0 / 12.0;
  }
  return 2.0775;
}

CfcCoefficients ComputeCfcCoefficients(double cfc_hz, double dt_s, CfcVariant variant) {
  const double wa = PrewarpedCutoff(cfc_hz, dt_s, variant);
  const double wa2 = wa * wa;
  const double sqrt2_wa = std::sqrt(2.0) * wa;
  const double d = 1.0 + sqrt2_wa + wa2;
  CfcCoefficients c;
  c.a0 = wa2 / d;
  c.a1 = 2.0 * c.a0;
  c.a2 = c.a0;
  c.b1 = -2.0 * (wa2 - 1.0) / d;
  c.b2 = (-1.0 + sqrt2_wa - wa2) / d;
  return c;
}

double CfcTwoPassGain(double frequency_hz, double cfc_hz, double dt_s, CfcVariant variant) {
  const double wa = PrewarpedCutoff(cfc_hz, dt_s, variant);
  const double ratio = std::tan(std::numbers::pi * frequency_hz * dt_s) / wa;
  const double ratio2 = ratio * ratio;
  return 1.0 / (1.0 + ratio2 * ratio2);
}

CfcFilter::CfcFilter(double cfc_hz, double dt_s, CfcVariant variant, double padding_s)
    : cfc_hz_(cfc_hz),
      dt_s_(dt_s),
      padding_s_(padding_s),
      coefficients_(ComputeCfcCoefficients(cfc_hz, dt_s, variant)) {
  if (!(std::isfinite(padding_s) && padding_s >= 0.0)) {
    std::ostringstream message;
    message << "the CFC filter padding " << padding_s << " s is not a non-negative duration.";
    throw InputError(message.str());
  }
}

Eigen::Index CfcFilter::PaddingSamples(Eigen::Index n) const {
  if (n < 2) return 0;
  const double padding_s = std::max(padding_s_, 1.0 / cfc_hz_);
  const auto wanted = static_cast<Eigen::Index>(std::ceil(padding_s / dt_s_ - 1e-9));
  // A point reflection about an end sample can mirror at most n - 1 samples.
  return std::min(wanted, n - 1);
}

void CfcFilter::Apply(const Eigen::Ref<const Eigen::VectorXd>& input, Eigen::Ref<Eigen::VectorXd> output) {
  const Eigen::Index n = input.size();
  if (output.size() != n) throw InputError("the CFC filter output buffer does not match the input length.");
  if (n < 2) {
    if (n == 1) output[0] = input[0];
    return;
  }
  const Eigen::Index pad = PaddingSamples(n);
  const Eigen::Index total = n + 2 * pad;
  if (work_.size() < total) work_.resize(total);
  double* w = work_.data();
  // Point reflection about the end samples (SAE J211/1 recommends pre- and
  // post-event data; reflection keeps value and slope continuous).
  const double first = input[0];
  const double last = input[n - 1];
  for (Eigen::Index k = 1; k <= pad; ++k) {
    w[pad - k] = 2.0 * first - input[k];
    w[pad + n - 1 + k] = 2.0 * last - input[n - 1 - k];
  }
  for (Eigen::Index k = 0; k < n; ++k) w[pad + k] = input[k];
  RunPass(coefficients_, w, total, /*forward=*/true);
  RunPass(coefficients_, w, total, /*forward=*/false);
  for (Eigen::Index k = 0; k < n; ++k) output[k] = w[pad + k];
}

void CfcFilter::ApplyInPlaceToColumns(Eigen::Ref<Eigen::MatrixXd> samples,
                                      const std::vector<Eigen::Index>& columns,
                                      const std::atomic<bool>* cancel) {
  const Eigen::Index n = samples.rows();
  if (n < 2) return;  // fewer than 2 samples stay as they are
  const Eigen::Index pad = PaddingSamples(n);
  const Eigen::Index total = n + 2 * pad;
  constexpr auto kMaxLanes = static_cast<std::size_t>(kMaxVectors * kLanesPerVector);
  // As few groups as kMaxLanes allows, each of as few vectors as hold its
  // channels: nine channels are one group of three vectors.
  const std::size_t groups = (columns.size() + kMaxLanes - 1) / kMaxLanes;
  const std::size_t per_group = groups == 0 ? 0 : (columns.size() + groups - 1) / groups;
  const auto vectors = static_cast<int>((per_group + kLanesPerVector - 1) / kLanesPerVector);
  const Eigen::Index lanes_per_row = vectors * kLanesPerVector;
  if (work_.size() < total * lanes_per_row) work_.resize(total * lanes_per_row);
  double* w = work_.data();
  for (std::size_t group = 0; group < columns.size(); group += per_group) {
    const auto lanes = static_cast<Eigen::Index>(std::min(per_group, columns.size() - group));
    // The group's channels, each read and written sample after sample: the
    // interleaved buffer is filled and emptied row by row (a few sequential
    // streams, not a strided walk of the whole buffer per channel).
    std::array<double*, kMaxLanes> channel{};
    std::array<double, kMaxLanes> first{}, last{};
    for (Eigen::Index lane = 0; lane < lanes; ++lane) {
      channel[static_cast<std::size_t>(lane)] =
          samples.col(columns[group + static_cast<std::size_t>(lane)]).data();
      first[static_cast<std::size_t>(lane)] = channel[static_cast<std::size_t>(lane)][0];
      last[static_cast<std::size_t>(lane)] = channel[static_cast<std::size_t>(lane)][n - 1];
    }
    // Each row of the buffer written whole, its unused lanes with zeros (they
    // filter zeros: no NaN, no denormal, nothing stored), in one loop with
    // the samples (no call to memset per row).
    const auto row_of = [&](Eigen::Index k) { return w + k * lanes_per_row; };
    // Apply's point reflection about the end samples.
    for (Eigen::Index k = 1; k <= pad; ++k) {
      double* before = row_of(pad - k);
      double* after = row_of(pad + n - 1 + k);
      for (Eigen::Index lane = 0; lane < lanes_per_row; ++lane) {
        const auto l = static_cast<std::size_t>(lane);
        before[lane] = lane < lanes ? 2.0 * first[l] - channel[l][k] : 0.0;
        after[lane] = lane < lanes ? 2.0 * last[l] - channel[l][n - 1 - k] : 0.0;
      }
    }
    for (Eigen::Index k = 0; k < n; ++k) {
      ThrowIfCancelled(cancel, k);
      double* row = row_of(pad + k);
      for (Eigen::Index lane = 0; lane < lanes_per_row; ++lane)
        row[lane] = lane < lanes ? channel[static_cast<std::size_t>(lane)][k] : 0.0;
    }
    RunPassesInterleaved(coefficients_, w, total, vectors, cancel);
    for (Eigen::Index k = 0; k < n; ++k) {
      ThrowIfCancelled(cancel, k);
      const double* row = row_of(pad + k);
      for (Eigen::Index lane = 0; lane < lanes; ++lane)
        channel[static_cast<std::size_t>(lane)][k] = row[lane];
    }
  }
}

// NOLINTNEXTLINE(performance-unnecessary-value-param): copies the view, never the signal (cfc_filter.h)
void CfcFilterInPlace(Eigen::Ref<Eigen::VectorXd> signal, double dt_s, double cfc_hz, CfcVariant variant) {
  CfcFilter filter(cfc_hz, dt_s, variant);
  filter.ApplyInPlace(signal);
}

}  // namespace napkin::engine
