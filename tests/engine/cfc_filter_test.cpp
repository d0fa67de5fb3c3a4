// CFC filters (SAE J211/1 Appendix C, ISO 6487): known coefficients, the
// analytic two-pass magnitude response on long sines, zero phase, DC and
// straight lines through the padded ends.
#include "engine/cfc_filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <random>
#include <vector>

#include "common/error.h"
#include "engine/units.h"

namespace napkin::engine {
namespace {

// |H(e^{j 2 pi f T})|^2 of one pass, evaluated from the coefficients alone
// (independent of the closed form in CfcTwoPassGain).
double OnePassPowerFromCoefficients(const CfcCoefficients& c, double frequency_hz, double dt_s) {
  const std::complex<double> z_inv = std::polar(1.0, -2.0 * std::numbers::pi * frequency_hz * dt_s);
  const std::complex<double> numerator = c.a0 + c.a1 * z_inv + c.a2 * z_inv * z_inv;
  const std::complex<double> denominator = 1.0 - c.b1 * z_inv - c.b2 * z_inv * z_inv;
  return std::norm(numerator / denominator);
}

TEST(CfcFilter, Sae1000At10kHzMatchesJ211KnownCoefficients) {
  const CfcCoefficients c = ComputeCfcCoefficients(kCfc1000, 1e-4, CfcVariant::kSaeJ211);
  EXPECT_NEAR(c.a0, 0.2192314172, 1e-10);
  EXPECT_NEAR(c.a1, 2.0 * 0.2192314172, 2e-10);
  EXPECT_NEAR(c.a2, 0.2192314172, 1e-10);
  EXPECT_NEAR(c.b1, 0.3118965450, 1e-10);
  EXPECT_NEAR(c.b2, -0.1888222139, 1e-10);
}

TEST(CfcFilter, OnePassIsMinus3dBAtTheDesignFrequencyOfEachVariant) {
  for (const CfcVariant variant : {CfcVariant::kSaeJ211, CfcVariant::kIso6487}) {
    for (const double cfc : {kCfc60, kCfc180, kCfc600, kCfc1000, 333.0}) {
      for (const double dt : {1e-4, 5e-5, 1.0 / 12500.0}) {
        const CfcCoefficients c = ComputeCfcCoefficients(cfc, dt, variant);
        const double design_hz = cfc * CfcDesignFactor(variant);
        EXPECT_NEAR(OnePassPowerFromCoefficients(c, design_hz, dt), 0.5, 1e-12) << cfc << " " << dt;
        // Unit DC gain; 1 - b1 - b2 = 4 wa^2 / D cancels to ~eps / wa^2 at low classes.
        EXPECT_NEAR(OnePassPowerFromCoefficients(c, 0.0, dt), 1.0, 1e-12);
      }
    }
  }
  EXPECT_DOUBLE_EQ(CfcDesignFactor(CfcVariant::kIso6487), 25.0 / 12.0);
  EXPECT_DOUBLE_EQ(CfcDesignFactor(CfcVariant::kSaeJ211), 2.0775);
}

TEST(CfcFilter, ClosedFormTwoPassGainEqualsTransferFunction) {
  for (const CfcVariant variant : {CfcVariant::kSaeJ211, CfcVariant::kIso6487}) {
    const double dt = 1e-4;
    const CfcCoefficients c = ComputeCfcCoefficients(kCfc600, dt, variant);
    for (double f = 0.0; f < 4900.0; f += 97.0) {
      const double one_pass = OnePassPowerFromCoefficients(c, f, dt);
      EXPECT_NEAR(CfcTwoPassGain(f, kCfc600, dt, variant), one_pass, 1e-13) << f;
    }
  }
}

TEST(CfcFilter, TwoPassGainAtTheClassFrequencyIsInsideTheJ211Corridor) {
  // SAE J211/1: at f = CFC the channel gain lies within +0.5 / -1 dB; the
  // two-pass Butterworth gives about -0.9 dB there and -3 dB near 1.67 CFC.
  for (const double cfc : {kCfc60, kCfc180, kCfc600, kCfc1000}) {
    const double gain_db = 20.0 * std::log10(CfcTwoPassGain(cfc, cfc, 1e-5));
    EXPECT_LT(gain_db, 0.5);
    EXPECT_GT(gain_db, -1.0);
    EXPECT_NEAR(20.0 * std::log10(CfcTwoPassGain(1.6667 * cfc, cfc, 1e-5)), -3.0103, 0.02);
  }
}

// Long sines: interior samples equal |H|^2 times the input (zero phase,
// analytic magnitude) to 1e-6.
TEST(CfcFilter, LongSinesAreScaledByTheAnalyticTwoPassGainWithZeroPhase) {
  const double dt = 1e-4;
  const Eigen::Index n = 20001;      // 2 s
  const Eigen::Index margin = 1000;  // 0.1 s kept clear of the end transients
  for (const CfcVariant variant : {CfcVariant::kSaeJ211, CfcVariant::kIso6487}) {
    for (const double cfc : {kCfc60, kCfc180, kCfc600, kCfc1000}) {
      CfcFilter filter(cfc, dt, variant);
      for (const double ratio : {0.1, 0.5, 1.0, 1.6667, 2.0, 3.0}) {
        const double f = ratio * cfc * 1.0000371;  // not commensurate with the rate
        if (f > 4500.0) continue;
        Eigen::VectorXd x(n), y(n);
        for (Eigen::Index k = 0; k < n; ++k) x[k] = std::sin(2.0 * std::numbers::pi * f * k * dt + 0.3);
        filter.Apply(x, y);
        const double gain = CfcTwoPassGain(f, cfc, dt, variant);
        double worst = 0.0;
        for (Eigen::Index k = margin; k < n - margin; ++k)
          worst = std::max(worst, std::abs(y[k] - gain * x[k]));
        EXPECT_LT(worst, 1e-6) << "cfc " << cfc << " f " << f << " gain " << gain;
      }
    }
  }
}

TEST(CfcFilter, ConstantsPassUnchangedIncludingTheEnds) {
  for (const double cfc : {kCfc60, kCfc1000, 7.5}) {
    for (const Eigen::Index n : {2, 3, 17, 5000}) {
      Eigen::VectorXd x = Eigen::VectorXd::Constant(n, -3.75);
      CfcFilterInPlace(x, 1e-4, cfc);
      EXPECT_LT((x.array() + 3.75).abs().maxCoeff(), 1e-12) << cfc << " " << n;
    }
  }
}

TEST(CfcFilter, StraightLinesPassUnchangedIncludingTheEnds) {
  // Point reflection continues a line across the ends; the zero-phase
  // recursion reproduces it once the start-up transient has died in the pad.
  const double dt = 1e-4;
  Eigen::VectorXd x(3000);
  for (Eigen::Index k = 0; k < x.size(); ++k) x[k] = 2.0 - 40.0 * k * dt;
  Eigen::VectorXd y(x.size());
  CfcFilter filter(kCfc1000, dt);
  filter.Apply(x, y);
  EXPECT_LT((y - x).cwiseAbs().maxCoeff(), 1e-9);
  CfcFilter filter60(kCfc60, dt);
  filter60.Apply(x, y);
  EXPECT_LT((y - x).cwiseAbs().maxCoeff(), 1e-5);  // 1e-6 of the 12 units the line spans
}

TEST(CfcFilter, SymmetricPulseStaysCentredAndSymmetric) {
  const double dt = 1e-4;
  const Eigen::Index n = 4001, centre = 2000;
  Eigen::VectorXd x(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const double t = (k - centre) * dt;
    x[k] = 80.0 * std::exp(-0.5 * std::pow(t / 0.002, 2)) + (std::abs(t) < 0.001 ? 10.0 : 0.0);
  }
  for (const double cfc : {kCfc60, kCfc180, kCfc1000}) {
    Eigen::VectorXd y(n);
    CfcFilter filter(cfc, dt);
    filter.Apply(x, y);
    Eigen::Index peak = 0;
    y.maxCoeff(&peak);
    EXPECT_EQ(peak, centre) << cfc;
    double asymmetry = 0.0;
    for (Eigen::Index k = 1; k < 1500; ++k)
      asymmetry = std::max(asymmetry, std::abs(y[centre + k] - y[centre - k]));
    EXPECT_LT(asymmetry, 1e-9) << cfc;
    EXPECT_LT(y[centre], x[centre]);  // low-pass lowers the peak
  }
}

TEST(CfcFilter, InPlaceAndOutputBufferAgreeAndBuffersAreReused) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 5.0);
  Eigen::MatrixXd channels(2500, 3);
  for (Eigen::Index k = 0; k < channels.size(); ++k) channels.data()[k] = noise(rng);
  CfcFilter filter(kCfc180, 1e-4, CfcVariant::kIso6487);
  Eigen::MatrixXd out(channels.rows(), 3);
  for (int c = 0; c < 3; ++c) filter.Apply(channels.col(c), out.col(c));
  Eigen::MatrixXd in_place = channels;
  for (int c = 0; c < 3; ++c) filter.ApplyInPlace(in_place.col(c));
  EXPECT_EQ(out, in_place);
  // A shorter signal after a longer one uses the same buffer correctly.
  Eigen::VectorXd shorter = channels.col(0).head(100);
  Eigen::VectorXd expected(100);
  CfcFilter fresh(kCfc180, 1e-4, CfcVariant::kIso6487);
  fresh.Apply(shorter, expected);
  filter.ApplyInPlace(shorter);
  EXPECT_EQ(shorter, expected);
  // Noise power drops.
  EXPECT_LT(out.col(0).squaredNorm(), 0.5 * channels.col(0).squaredNorm());
}

// Several channels at once equal one channel at a time, bit for bit: any
// number of columns (a partial group of four too), any subset and order,
// lengths shorter than the padding, and untouched columns left alone.
TEST(CfcFilter, ColumnsFilteredTogetherEqualOneAtATimeBitForBit) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0.0, 20.0);
  for (const Eigen::Index n : {2, 3, 40, 1000, 2501}) {
    Eigen::MatrixXd channels(n, 10);
    for (Eigen::Index k = 0; k < channels.size(); ++k) channels.data()[k] = noise(rng);
    for (const std::vector<Eigen::Index>& columns :
         {std::vector<Eigen::Index>{0}, {3, 1}, {0, 1, 2, 3}, {9, 2, 5, 7, 0}, {0, 1, 2, 3, 4, 5, 6, 7, 8}}) {
      CfcFilter filter(kCfc1000, 1e-4);
      Eigen::MatrixXd expected = channels;
      for (const Eigen::Index c : columns) filter.ApplyInPlace(expected.col(c));
      Eigen::MatrixXd together = channels;
      filter.ApplyInPlaceToColumns(together, columns);
      ASSERT_EQ(together, expected) << "n " << n << ", " << columns.size() << " columns";
      if (n > 3) {
        EXPECT_NE(together.col(columns.front()), channels.col(columns.front()));
      }
    }
  }
}

TEST(CfcFilter, PaddingIsAtLeastTenMillisecondsAndOneClassPeriod) {
  CfcFilter f1000(kCfc1000, 1e-4);
  EXPECT_EQ(f1000.PaddingSamples(10000), 100);
  EXPECT_EQ(f1000.PaddingSamples(50), 49);  // limited by the reflection
  CfcFilter f60(kCfc60, 1e-4);
  EXPECT_EQ(f60.PaddingSamples(10000), 167);  // 1/60 s
}

TEST(CfcFilter, BadParametersAreInputErrors) {
  EXPECT_THROW(ComputeCfcCoefficients(0.0, 1e-4), InputError);
  EXPECT_THROW(ComputeCfcCoefficients(-60.0, 1e-4), InputError);
  EXPECT_THROW(ComputeCfcCoefficients(std::nan(""), 1e-4), InputError);
  EXPECT_THROW(ComputeCfcCoefficients(1000.0, 0.0), InputError);
  EXPECT_THROW(ComputeCfcCoefficients(1000.0, 1.0 / 4000.0), InputError);  // design frequency past Nyquist
  EXPECT_NO_THROW(ComputeCfcCoefficients(1000.0, 1.0 / 5000.0));
  EXPECT_THROW(CfcFilter(60.0, 1e-4, CfcVariant::kSaeJ211, -1.0), InputError);
  CfcFilter filter(60.0, 1e-4);
  Eigen::VectorXd in(10), out(9);
  EXPECT_THROW(filter.Apply(in, out), InputError);
}

}  // namespace
}  // namespace napkin::engine
