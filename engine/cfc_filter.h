#pragma once
// Channel frequency class (CFC) filters, SAE J211/1 Appendix C and the
// ISO 6487 variant: a second-order Butterworth low-pass (bilinear transform
// with pre-warping) run forward then backward, so the combined response is
// phaseless with |H|^2 magnitude (a fourth-order Butterworth magnitude).
//
//   omega_d = 2 pi CFC k   (k = 2.0775 SAE J211, k = 25/12 ISO 6487)
//   omega_a = tan(omega_d T / 2),   D = 1 + sqrt(2) omega_a + omega_a^2
//   a0 = omega_a^2 / D,  a1 = 2 a0,  a2 = a0
//   b1 = -2 (omega_a^2 - 1) / D,  b2 = (-1 + sqrt(2) omega_a - omega_a^2) / D
//   y[t] = a0 x[t] + a1 x[t-1] + a2 x[t-2] + b1 y[t-1] + b2 y[t-2]
//
// Amplitude gain of the two passes at frequency f (= the power gain |H|^2 of
// one pass; exact for this bilinear design):
//   G(f) = |H(f)|^2 = 1 / (1 + (tan(pi f T) / omega_a)^4),
// i.e. -0.45 dB at f = CFC and -3 dB at about 1.667 CFC (SAE), inside the
// J211 corridor. Ends are padded (>= 10 ms, point reflection about the end
// samples) and the filter starts in the steady state of the first padded
// value, so constants and straight lines pass unchanged, ends included.
#include <Eigen/Core>
#include <array>
#include <atomic>
#include <optional>
#include <string_view>
#include <vector>

#include "engine/vocabulary.h"

namespace napkin::engine {

enum class CfcVariant {
  kSaeJ211,  // omega_d = 2 pi CFC 2.0775 (SAE J211/1 Appendix C)
  kIso6487,  // omega_d = 2 pi CFC 25/12 (ISO 6487)
};

inline constexpr std::array<NamedValue<CfcVariant>, 2> kCfcVariantNames{
    {{CfcVariant::kSaeJ211, "sae"}, {CfcVariant::kIso6487, "iso"}}};
inline constexpr std::array<CfcVariant, 2> kCfcVariants = ValuesOf(kCfcVariantNames);

// The one spelling of each variant in processing configs ("sae", "iso"), and
// its inverse (nullopt for an unknown name).
constexpr const auto& NamesOf(CfcVariant) { return kCfcVariantNames; }

// The standard channel classes; any positive frequency is accepted too.
inline constexpr double kCfc60 = 60.0;
inline constexpr double kCfc180 = 180.0;
inline constexpr double kCfc600 = 600.0;
inline constexpr double kCfc1000 = 1000.0;

// SAE J211/1 names each standard class by a number but states its cut-off
// frequency F_H (the -3 dB point) in Hz: CFC 60 100 Hz, CFC 180 300 Hz,
// CFC 600 1000 Hz, CFC 1000 1650 Hz. Files that record a filter as a
// frequency (UDS-1992 FCUT, docs/formats.md "UDS-1992 input") give F_H.
//
// The standard class whose cut-off is within kJ211CutoffTolerance of
// `cutoff_hz` (NHTSA's files carry 1662 Hz for CFC 1000; neighbouring
// cut-offs are at least a factor 1.65 apart), nullopt for any other
// frequency.
inline constexpr double kJ211CutoffTolerance = 0.02;  // relative
std::optional<double> J211ClassOfCutoff(double cutoff_hz);
// The cut-off of class `cfc`: J211's F_H for the four standard classes (1e-9
// relative tolerance), else 5/3 CFC (the ratio of the standard classes 60,
// 180 and 600, and about where this filter's gain is -3 dB).
double J211CutoffOfClass(double cfc);

struct CfcCoefficients {
  double a0 = 0.0, a1 = 0.0, a2 = 0.0;  // feed-forward (on x[t], x[t-1], x[t-2])
  double b1 = 0.0, b2 = 0.0;            // feedback (on y[t-1], y[t-2]), J211 sign convention
};

// Design factor k in omega_d = 2 pi CFC k.
double CfcDesignFactor(CfcVariant variant);

// Coefficients of one pass for class `cfc_hz` at sampling interval `dt_s`.
// Throws InputError when cfc_hz or dt_s is not positive and finite, or when
// the design frequency reaches Nyquist (omega_d T / 2 >= pi / 2).
CfcCoefficients ComputeCfcCoefficients(double cfc_hz, double dt_s, CfcVariant variant = CfcVariant::kSaeJ211);

// Exact amplitude gain G(f) = |H(f)|^2 of the forward + backward filter: a
// sine of frequency f comes out multiplied by G(f), with no phase shift.
double CfcTwoPassGain(double frequency_hz, double cfc_hz, double dt_s,
                      CfcVariant variant = CfcVariant::kSaeJ211);

// A configured filter for one class and sampling interval. Reuses an
// internal padded work buffer, so filtering many channels of one length
// allocates once; the per-sample loops never allocate.
class CfcFilter {
 public:
  // padding_s: length of the reflected padding at each end; the effective
  // padding is max(padding_s, 1 / cfc_hz) (at least one period of the class
  // frequency), limited to the n - 1 samples a point reflection can use.
  CfcFilter(double cfc_hz, double dt_s, CfcVariant variant = CfcVariant::kSaeJ211, double padding_s = 0.010);

  const CfcCoefficients& coefficients() const { return coefficients_; }
  double cfc_hz() const { return cfc_hz_; }
  double dt_s() const { return dt_s_; }
  // Padding (samples) used at each end for a signal of n samples.
  Eigen::Index PaddingSamples(Eigen::Index n) const;

  // output = filtered input (same length; output may alias input).
  // Signals of fewer than 2 samples are copied unchanged.
  void Apply(const Eigen::Ref<const Eigen::VectorXd>& input, Eigen::Ref<Eigen::VectorXd> output);
  // A writable Eigen::Ref is a view (pointer, size, stride), passed by value as Eigen's guide
  // "Writing Functions Taking Eigen Types as Parameters" does: the samples are written through its
  // copies, which a const reference would only hide.
  // NOLINTNEXTLINE(performance-unnecessary-value-param): copies the view, never the signal
  void ApplyInPlace(Eigen::Ref<Eigen::VectorXd> signal) { Apply(signal, signal); }

  // ApplyInPlace on each of `columns` of `samples` (one channel per column),
  // with exactly its arithmetic, so the results are bit-identical. The
  // recursions of different channels are independent, so they run up to
  // twelve abreast (nine channels in one group): each output waits on the
  // channel's previous output (a chain of multiply-adds), and interleaving
  // channels fills the pipeline meanwhile (napkin_bench
  // --benchmark_filter=NineChannels). Throws Cancelled once
  // `cancel` is set (engine/cancellation.h).
  void ApplyInPlaceToColumns(Eigen::Ref<Eigen::MatrixXd> samples, const std::vector<Eigen::Index>& columns,
                             const std::atomic<bool>* cancel = nullptr);

  // Exchanges the work buffer with `buffer`: a caller that filters test
  // after test lends the filter its buffer and takes it back, so the padded
  // channels land in memory already mapped (engine/pipeline.h Workspace).
  void SwapWork(Eigen::VectorXd& buffer) { work_.swap(buffer); }

 private:
  double cfc_hz_;
  double dt_s_;
  double padding_s_;
  CfcCoefficients coefficients_;
  Eigen::VectorXd work_;  // padded signal, grown on demand
};

// One-shot convenience: filters `signal` in place (a view passed by value, as ApplyInPlace).
void CfcFilterInPlace(Eigen::Ref<Eigen::VectorXd> signal, double dt_s, double cfc_hz,
                      CfcVariant variant = CfcVariant::kSaeJ211);

}  // namespace napkin::engine
