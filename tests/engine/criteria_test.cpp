// a3ms, BrIC, DAMAGE and FillCriteria: brute-force definitions, closed-form
// oscillator responses, a fine-step RK4 reference and the report's 4.5 scenario.
#include "engine/criteria.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "common/error.h"
#include "engine/report_known_answers.h"
#include "engine/units.h"

namespace napkin::engine {
namespace {

// a3ms by its definition: the largest sample level L such that the samples
// at or above L last at least 3 ms in total (each sample stands for dt).
double BruteForceA3ms(const Eigen::VectorXd& a, double dt) {
  double best = -std::numeric_limits<double>::infinity();
  for (Eigen::Index candidate = 0; candidate < a.size(); ++candidate) {
    const double level = a[candidate];
    const double time_above = static_cast<double>((a.array() >= level).count()) * dt;
    if (time_above >= 0.003 - 1e-12 && level > best) best = level;
  }
  return best;
}

TEST(A3ms, EqualsTheBruteForceDefinition) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int trial = 0; trial < 60; ++trial) {
    const double dt = trial % 3 == 0 ? 1e-4 : (trial % 3 == 1 ? 5e-5 : 1.0 / 12500.0);
    const Eigen::Index n = 60 + static_cast<Eigen::Index>(uniform(rng) * 800);
    Eigen::VectorXd a(n);
    for (Eigen::Index k = 0; k < n; ++k)
      a[k] =
          trial % 4 == 0 ? std::floor(uniform(rng) * 5.0) : 100.0 * uniform(rng) * uniform(rng);  // ties too
    EXPECT_EQ(A3ms(a, dt), BruteForceA3ms(a, dt)) << trial;
  }
}

TEST(A3ms, CountsCumulativeNotContinuousTime) {
  // Two separate 2 ms blocks at 80 g: 4 ms in total above 80 g -> a3ms = 80.
  Eigen::VectorXd a = Eigen::VectorXd::Constant(500, 10.0);
  a.segment(50, 20).setConstant(80.0);
  a.segment(300, 20).setConstant(80.0);
  EXPECT_EQ(A3ms(a, 1e-4), 80.0);
  // At 10 kHz, 3 ms is 30 samples: the 30th largest.
  Eigen::VectorXd ramp = Eigen::VectorXd::LinSpaced(100, 1.0, 100.0);
  EXPECT_EQ(A3ms(ramp, 1e-4), 71.0);
}

TEST(A3ms, HalfSineMatchesTheContinuousLevel) {
  // A sin(pi t / T): time above L is T - 2 (T / pi) asin(L / A); 3 ms above
  // at L = A cos(pi 3 ms / (2 T)). Sampling moves it by at most one step of slope.
  const double amplitude = 90.0, duration = 0.012, dt = 1e-5;
  const auto n = static_cast<Eigen::Index>(std::llround(duration / dt)) + 1;
  Eigen::VectorXd a(n);
  for (Eigen::Index k = 0; k < n; ++k)
    a[k] = amplitude * std::sin(std::numbers::pi * static_cast<double>(k) * dt / duration);
  const double expected = amplitude * std::cos(std::numbers::pi * 0.003 / (2.0 * duration));
  EXPECT_NEAR(A3ms(a, dt), expected, amplitude * std::numbers::pi / duration * dt);
}

TEST(A3ms, ShortRecordsAndBadInputAreInputErrors) {
  EXPECT_THROW(A3ms(Eigen::VectorXd::Ones(29), 1e-4), InputError);
  EXPECT_NO_THROW(A3ms(Eigen::VectorXd::Ones(30), 1e-4));
  EXPECT_THROW(A3ms(Eigen::VectorXd::Ones(100), -1e-4), InputError);
}

TEST(Bric, IsTheRootSumOfSquaresOfNormalisedPeaks) {
  Series3 omega = Series3::Zero(200, 3);
  omega(50, 0) = -66.25;  // negative peaks count by magnitude
  omega(80, 1) = 20.0;
  omega(81, 1) = -56.45 / 2.0;
  omega(10, 2) = 42.87 * 2.0;
  const Eigen::Vector3d critical(66.25, 56.45, 42.87);
  EXPECT_NEAR(Bric(omega, critical), std::sqrt(1.0 + 0.25 + 4.0), 1e-14);
  EXPECT_NEAR(Bric(omega, Eigen::Vector3d(1.0, 1.0, 1.0)), Eigen::Vector3d(66.25, 28.225, 85.74).norm(),
              1e-12);
  EXPECT_THROW(Bric(omega, Eigen::Vector3d(1.0, 0.0, 1.0)), InputError);
}

// ---------------------------------------------------------------------------
// DAMAGE

// Closed-form response of q'' + 2 zeta w q' + w^2 q = f(t) from rest, for a
// step f = f0 (t >= 0).
double StepResponse(double f0, double w, double zeta, double t) {
  const double wd = w * std::sqrt(1.0 - zeta * zeta);
  return f0 / (w * w) *
         (1.0 - std::exp(-zeta * w * t) *
                    (std::cos(wd * t) + zeta / std::sqrt(1.0 - zeta * zeta) * std::sin(wd * t)));
}

// ... for f = A sin(W t) from rest.
double SineResponse(double amplitude, double forcing, double w, double zeta, double t) {
  const double c = 2.0 * zeta * w * forcing, k = w * w - forcing * forcing;
  const double p = amplitude * k / (k * k + c * c),
               q = -amplitude * c / (k * k + c * c);  // q_p = p sin + q cos
  const double wd = w * std::sqrt(1.0 - zeta * zeta);
  const double c1 = -q;
  const double c2 = (zeta * w * c1 - p * forcing) / wd;
  return p * std::sin(forcing * t) + q * std::cos(forcing * t) +
         std::exp(-zeta * w * t) * (c1 * std::cos(wd * t) + c2 * std::sin(wd * t));
}

TEST(Damage, StepOnTheDecoupledYAxisMatchesTheClosedForm) {
  // kxy = kyz = 0: the y axis is a single oscillator, w^2 = kyy / m,
  // 2 zeta w = a1 kyy / m. A constant alpha is exactly piecewise linear.
  const DamageModel model;
  const double dt = 1e-4, alpha = 3000.0;
  Series3 alpha_body = Series3::Zero(1001, 3);
  alpha_body.col(1).setConstant(alpha);
  const Series3 d = DamageDisplacement(alpha_body, dt, model);
  const double w = std::sqrt(model.kyy / model.mass_kg);
  const double zeta = model.a1_s * model.kyy / model.mass_kg / (2.0 * w);
  double worst = 0.0, peak = 0.0;
  for (Eigen::Index k = 0; k < d.rows(); ++k) {
    const double expected = StepResponse(alpha, w, zeta, static_cast<double>(k) * dt);
    worst = std::max(worst, std::abs(d(k, 1) - expected));
    peak = std::max(peak, std::abs(expected));
  }
  EXPECT_LT(worst, 1e-11 * peak);
  EXPECT_LT(d.col(0).cwiseAbs().maxCoeff(), 1e-300);  // no coupling into x or z
  EXPECT_LT(d.col(2).cwiseAbs().maxCoeff(), 1e-300);
  EXPECT_NEAR(Damage(alpha_body, dt, model), model.beta_per_m * d.rowwise().norm().maxCoeff(), 1e-15);
}

TEST(Damage, SineOnTheYAxisConvergesToTheClosedFormAtSecondOrder) {
  // Linear interpolation of a smooth alpha is the only error: O(dt^2).
  const DamageModel model;
  const double w = std::sqrt(model.kyy), zeta = model.a1_s * model.kyy / (2.0 * w);
  const double amplitude = 2500.0, forcing = 2.0 * std::numbers::pi * 40.0;
  double previous_error = 0.0;
  for (const double dt : {2e-4, 1e-4, 5e-5}) {
    const auto n = static_cast<Eigen::Index>(std::llround(0.1 / dt)) + 1;
    Series3 alpha_body = Series3::Zero(n, 3);
    for (Eigen::Index k = 0; k < n; ++k)
      alpha_body(k, 1) = amplitude * std::sin(forcing * static_cast<double>(k) * dt);
    const Series3 d = DamageDisplacement(alpha_body, dt, model);
    double error = 0.0, peak = 0.0;
    for (Eigen::Index k = 0; k < n; ++k) {
      const double expected = SineResponse(amplitude, forcing, w, zeta, static_cast<double>(k) * dt);
      error = std::max(error, std::abs(d(k, 1) - expected));
      peak = std::max(peak, std::abs(expected));
    }
    // Linear interpolation misses alpha by at most (W dt)^2 / 8 of its
    // amplitude; allow twice that relative to the response.
    EXPECT_LT(error, std::pow(forcing * dt, 2) / 4.0 * peak) << dt;
    if (previous_error > 0.0) {
      EXPECT_NEAR(previous_error / error, 4.0, 0.4) << dt;
    }
    previous_error = error;
  }
}

// Fine-step RK4 of the full coupled system with alpha interpolated linearly
// between samples (the same input the exact discretisation sees).
Series3 Rk4Reference(const Series3& alpha, double dt, const DamageModel& model, int substeps) {
  const Eigen::Matrix3d k = model.Stiffness() / model.mass_kg;
  const Eigen::Matrix3d c = model.a1_s * k;
  using State = Eigen::Matrix<double, 6, 1>;
  const auto derivative = [&](const State& x, const Eigen::Vector3d& a) {
    State dx;
    dx.head<3>() = x.tail<3>();
    dx.tail<3>() = a - k * x.head<3>() - c * x.tail<3>();
    return dx;
  };
  Series3 out = Series3::Zero(alpha.rows(), 3);
  State x = State::Zero();
  const double h = dt / substeps;
  for (Eigen::Index s = 0; s + 1 < alpha.rows(); ++s) {
    const Eigen::Vector3d a0 = alpha.row(s).transpose(), a1 = alpha.row(s + 1).transpose();
    const auto input = [&](double u) -> Eigen::Vector3d { return a0 + u * (a1 - a0); };
    for (int m = 0; m < substeps; ++m) {
      const double u = static_cast<double>(m) / substeps, du = 1.0 / substeps;
      const State k1 = derivative(x, input(u));
      const State k2 = derivative(x + 0.5 * h * k1, input(u + 0.5 * du));
      const State k3 = derivative(x + 0.5 * h * k2, input(u + 0.5 * du));
      const State k4 = derivative(x + h * k3, input(u + du));
      x += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    out.row(s + 1) = x.head<3>().transpose();
  }
  return out;
}

TEST(Damage, CoupledPulsesMatchAFineStepRk4Reference) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double dt = 1e-4;
  const Eigen::Index n = 1501;
  Series3 alpha = Series3::Zero(n, 3);
  for (int axis = 0; axis < 3; ++axis) {
    for (int pulse = 0; pulse < 3; ++pulse) {
      const double start = uniform(rng) * 0.08, length = 0.005 + 0.02 * uniform(rng);
      const double height = 6000.0 * (uniform(rng) - 0.5);
      for (Eigen::Index k = 0; k < n; ++k) {
        const double s = (static_cast<double>(k) * dt - start) / length;
        if (s >= 0.0 && s <= 1.0)
          alpha(k, axis) += height * 0.5 * (1.0 - std::cos(2.0 * std::numbers::pi * s));
      }
    }
  }
  const DamageModel model;
  const Series3 exact = DamageDisplacement(alpha, dt, model);
  const Series3 reference = Rk4Reference(alpha, dt, model, 20);
  const double scale = reference.cwiseAbs().maxCoeff();
  EXPECT_LT((exact - reference).cwiseAbs().maxCoeff(), 1e-9 * scale);
  // The x-z coupling (kxz) is exercised: x responds to a z-only input.
  Series3 z_only = Series3::Zero(n, 3);
  z_only.col(2) = alpha.col(2);
  EXPECT_GT(DamageDisplacement(z_only, dt, model).col(0).cwiseAbs().maxCoeff(), 1e-4 * scale);
  EXPECT_NEAR(Damage(alpha, dt, model), model.beta_per_m * reference.rowwise().norm().maxCoeff(),
              1e-8 * scale);
}

// ---------------------------------------------------------------------------

TEST(HicD, IsTheFmvss201LinearMapOfHic36) {
  // FMVSS No. 201 S6.3: HIC(d) = 0.75446 HIC36 + 166.4, so its limit of 1000
  // corresponds to HIC36 = (1000 - 166.4) / 0.75446 = 1104.89...
  EXPECT_NEAR(HicD((1000.0 - 166.4) / 0.75446), 1000.0, 1e-9);
  EXPECT_NEAR(HicD(0.0), 166.4, 1e-12);
  EXPECT_NEAR(HicD(1000.0) - HicD(500.0), 0.75446 * 500.0, 1e-9);
  EXPECT_TRUE(std::isnan(HicD(std::numeric_limits<double>::quiet_NaN())));
}

TEST(FillCriteria, ReportSection45ScenarioFromKinematics) {
  // Rotation about an axis parallel to fixed Y through a point 10 in from the
  // CG: tangential r omega_dot and centripetal r omega^2 in the X-Z plane.
  const double r = 10.0 * kMetresPerInch, dt = 1e-4;
  const Eigen::Index n = 1001;
  Kinematics kinematics;
  kinematics.Resize(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * dt;
    double omega = 0.0, omega_dot = 0.0;
    if (t <= 0.06) {
      omega = 25.0 * (1.0 - std::cos(2.0 * std::numbers::pi * t / 0.06));
      omega_dot = 25.0 * (2.0 * std::numbers::pi / 0.06) * std::sin(2.0 * std::numbers::pi * t / 0.06);
    }
    kinematics.time_s[k] = t;
    const double angle = 0.5 + 0.1 * t;  // any direction in the X-Z plane
    kinematics.acc_fixed.row(k) << r * omega_dot * std::cos(angle) - r * omega * omega * std::sin(angle), 0.0,
        r * omega_dot * std::sin(angle) + r * omega * omega * std::cos(angle);
    kinematics.omega_body.row(k) << 0.1 * omega, omega, -0.2 * omega;
    kinematics.alpha_body.row(k) << 0.1 * omega_dot, omega_dot, -0.2 * omega_dot;
  }
  ProcessingConfig config;
  TestSummary summary;
  FillCriteria(kinematics, config, summary);
  EXPECT_NEAR(summary.hic.value, report::kHic, 0.01);
  EXPECT_NEAR(summary.hic.t1_s, report::kHicT1S, 1e-9);
  EXPECT_NEAR(summary.hic.t2_s, report::kHicT2S, 1e-9);
  EXPECT_NEAR(summary.hic36.value, report::kHic36, 0.01);
  EXPECT_NEAR(summary.hic15.value, report::kHic15, 0.01);
  EXPECT_NEAR(summary.hic_d, 0.75446 * report::kHic36 + 166.4, 0.75446 * 0.01);
  EXPECT_EQ(summary.hic_d, HicD(summary.hic36.value));
  const Eigen::VectorXd acc_g = kinematics.acc_fixed.rowwise().norm() / kStandardGravity;
  EXPECT_EQ(summary.a3ms_g, A3ms(acc_g, dt));
  EXPECT_NEAR(summary.bric, Eigen::Vector3d(5.0 / 66.25, 50.0 / 56.45, 10.0 / 42.87).norm(), 1e-12);
  EXPECT_EQ(summary.damage, Damage(kinematics.alpha_body, dt));
  EXPECT_GT(summary.damage, 0.0);

  config.bric.critical_radps = Eigen::Vector3d(10.0, 10.0, 10.0);
  FillCriteria(kinematics, config, summary);
  EXPECT_NEAR(summary.bric, Eigen::Vector3d(0.5, 5.0, 1.0).norm(), 1e-12);

  Kinematics too_short;
  too_short.Resize(1);
  EXPECT_THROW(FillCriteria(too_short, config, summary), InputError);
}

}  // namespace
}  // namespace napkin::engine
