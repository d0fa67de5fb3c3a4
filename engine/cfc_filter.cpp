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

// RunPass on kLanes channels stored interleaved (w[k * kLanes + lane]),
// each with RunPass's operations in RunPass's order: the lanes of a GCC
// vector are computed element-wise with IEEE arithmetic, as the scalars
// would be. Two-lane vectors (one SSE2 register, so no ABI or lowering
// surprises without -mavx), two of them per step: four independent chains.
// Coefficients and state live in locals (registers), not behind pointers
// the stores to w could alias.
using LaneVector = double __attribute__((vector_size(2 * sizeof(double))));
constexpr Eigen::Index kLanes = 4;

void RunPassInterleaved(const CfcCoefficients& c, double* w, Eigen::Index n, bool forward,
                        const std::atomic<bool>* cancel) {
  const LaneVector a0 = {c.a0, c.a0}, a1 = {c.a1, c.a1}, a2 = {c.a2, c.a2};
  const LaneVector b1 = {c.b1, c.b1}, b2 = {c.b2, c.b2};
  Eigen::Index k = forward ? 0 : n - 1;
  const Eigen::Index step = forward ? 1 : -1;
  LaneVector first_lo, first_hi;
  std::memcpy(&first_lo, w + k * kLanes, sizeof first_lo);
  std::memcpy(&first_hi, w + k * kLanes + 2, sizeof first_hi);
  LaneVector x1_lo = first_lo, x2_lo = first_lo, y1_lo = first_lo, y2_lo = first_lo;
  LaneVector x1_hi = first_hi, x2_hi = first_hi, y1_hi = first_hi, y2_hi = first_hi;
  for (Eigen::Index count = 0; count < n; ++count, k += step) {
    ThrowIfCancelled(cancel, count);
    double* row = w + k * kLanes;
    LaneVector x_lo, x_hi;
    std::memcpy(&x_lo, row, sizeof x_lo);
    std::memcpy(&x_hi, row + 2, sizeof x_hi);
    const LaneVector y_lo = a0 * x_lo + a1 * x1_lo + a2 * x2_lo + b1 * y1_lo + b2 * y2_lo;
    const LaneVector y_hi = a0 * x_hi + a1 * x1_hi + a2 * x2_hi + b1 * y1_hi + b2 * y2_hi;
    std::memcpy(row, &y_lo, sizeof y_lo);
    std::memcpy(row + 2, &y_hi, sizeof y_hi);
    x2_lo = x1_lo;
    x1_lo = x_lo;
    y2_lo = y1_lo;
    y1_lo = y_lo;
    x2_hi = x1_hi;
    x1_hi = x_hi;
    y2_hi = y1_hi;
    y1_hi = y_hi;
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
  if (work_.size() < total * kLanes) work_.resize(total * kLanes);
  double* w = work_.data();
  for (std::size_t group = 0; group < columns.size(); group += kLanes) {
    const std::size_t lanes = std::min<std::size_t>(kLanes, columns.size() - group);
    // Unused lanes filter zeros (no NaN, no denormal, nothing stored).
    if (lanes < static_cast<std::size_t>(kLanes)) std::fill(w, w + total * kLanes, 0.0);
    for (std::size_t lane = 0; lane < lanes; ++lane) {
      const auto input = samples.col(columns[group + lane]);
      const double first = input[0];
      const double last = input[n - 1];
      // Apply's point reflection about the end samples.
      for (Eigen::Index k = 1; k <= pad; ++k) {
        w[(pad - k) * kLanes + static_cast<Eigen::Index>(lane)] = 2.0 * first - input[k];
        w[(pad + n - 1 + k) * kLanes + static_cast<Eigen::Index>(lane)] = 2.0 * last - input[n - 1 - k];
      }
      for (Eigen::Index k = 0; k < n; ++k) {
        ThrowIfCancelled(cancel, k);
        w[(pad + k) * kLanes + static_cast<Eigen::Index>(lane)] = input[k];
      }
    }
    RunPassInterleaved(coefficients_, w, total, /*forward=*/true, cancel);
    RunPassInterleaved(coefficients_, w, total, /*forward=*/false, cancel);
    for (std::size_t lane = 0; lane < lanes; ++lane) {
      auto output = samples.col(columns[group + lane]);
      for (Eigen::Index k = 0; k < n; ++k) {
        ThrowIfCancelled(cancel, k);
        output[k] = w[(pad + k) * kLanes + static_cast<Eigen::Index>(lane)];
      }
    }
  }
}

// NOLINTNEXTLINE(performance-unnecessary-value-param): copies the view, never the signal (cfc_filter.h)
void CfcFilterInPlace(Eigen::Ref<Eigen::VectorXd> signal, double dt_s, double cfc_hz, CfcVariant variant) {
  CfcFilter filter(cfc_hz, dt_s, variant);
  filter.ApplyInPlace(signal);
}

}  // namespace napkin::engine
