// The synthetic generator's truth must be exact: self-consistent under
// numerical differentiation, and equal to the report's known answers.
#include "synth/synthetic_tests.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "engine/integration.h"
#include "engine/report_known_answers.h"
#include "engine/rotation.h"
#include "engine/units.h"
#include "tests/support/reference_arrays.h"

namespace napkin::engine {
namespace {

// The truth integrated by the trapezoid rule reproduces itself: value[k] -
// value[0] = sum of dt/2 (d[j-1] + d[j]) up to O(dt^2) (the motions are C1
// with kinks in the derivative, so differentiation would be too coarse a
// check and integration is not). `tolerance` is relative to the largest
// change of the value.
void ExpectSelfConsistent(const synth::SyntheticTest& test, double tolerance) {
  const Kinematics& truth = test.truth;
  const double dt = test.signals.dt_s;
  const Eigen::Index n = truth.size();
  ASSERT_GE(n, 3);
  auto check = [&](const Series3& value, const Series3& derivative, const char* what) {
    Eigen::RowVector3d integral = Eigen::RowVector3d::Zero();
    double worst = 0.0, scale = 0.0;
    for (Eigen::Index k = 1; k < n; ++k) {
      integral += 0.5 * dt * (derivative.row(k - 1) + derivative.row(k));
      const Eigen::RowVector3d change = value.row(k) - value.row(0);
      worst = std::max(worst, (integral - change).norm());
      scale = std::max(scale, change.norm());
    }
    EXPECT_LE(worst, tolerance * scale) << what;
  };
  check(truth.omega_body, truth.alpha_body, "d omega/dt = alpha");
  check(truth.omega_fixed, truth.alpha_fixed, "fixed: d omega/dt = alpha");
  check(truth.vel_fixed, truth.acc_fixed, "dv/dt = a");
  check(truth.pos_fixed, truth.vel_fixed, "dp/dt = v");
  // dR/dt = R [omega_body]x: the rotation from sample k-1 to k is
  // dt/2 (omega[k-1] + omega[k]) up to O(dt^3).
  const double omega_scale = truth.omega_body.rowwise().norm().maxCoeff();
  double worst = 0.0;
  for (Eigen::Index k = 1; k < n; ++k) {
    const Eigen::Vector3d step = QuaternionLog(QuatAt(truth.quat_fixed_from_body, k - 1).conjugate() *
                                               QuatAt(truth.quat_fixed_from_body, k));
    worst = std::max(
        worst,
        (step - 0.5 * dt * (truth.omega_body.row(k - 1) + truth.omega_body.row(k)).transpose()).norm());
  }
  EXPECT_LE(worst, tolerance * dt * omega_scale) << "dR/dt = R [omega]x";
  // Fixed-frame series are R times body series; angles are those of R.
  for (Eigen::Index k = 0; k < n; k += 97) {
    const Eigen::Matrix3d r = QuatAt(truth.quat_fixed_from_body, k).toRotationMatrix();
    EXPECT_LE((r * truth.omega_body.row(k).transpose() - truth.omega_fixed.row(k).transpose()).norm(), 1e-9);
    EXPECT_LE((r * truth.acc_body.row(k).transpose() - truth.acc_fixed.row(k).transpose()).norm(), 1e-9);
    const Eigen::Vector3d rpy = truth.roll_pitch_yaw_rad.row(k).transpose();
    EXPECT_LE((Rz(rpy.z()) * Ry(rpy.y()) * Rx(rpy.x()) - r).norm(), 1e-12);
  }
  // Orientation starts at R0 of the initial state.
  EXPECT_LE((QuatAt(truth.quat_fixed_from_body, 0).toRotationMatrix() -
             InitialFixedFromBody(test.initial.orientation_rad))
                .norm(),
            1e-14);
  EXPECT_LE((truth.vel_fixed.row(0).transpose() - test.initial.velocity_fixed_mps).norm(), 1e-14);
  EXPECT_EQ(truth.pos_fixed.row(0).norm(), 0.0);
}

TEST(Synth, SeedFixedAxisTruthIsTheReportScenario) {
  const synth::SyntheticTest test =
      synth::SynthSeedFixedAxis(test_support::Denton3222(), Eigen::Vector3d(0.5, 0.5, 0.5));
  const Kinematics& truth = test.truth;
  ASSERT_EQ(truth.size(), 1001);  // t = 0 ... 0.1 s inclusive at 10 kHz
  EXPECT_DOUBLE_EQ(truth.time_s(1000), 0.1);
  EXPECT_EQ(test.signals.slots.size(), 9u);
  ExpectSelfConsistent(test, 2e-4);
  // Known answers (docs/algorithms.md).
  const Eigen::Quaterniond turn =
      QuatAt(truth.quat_fixed_from_body, 1000) * QuatAt(truth.quat_fixed_from_body, 0).conjugate();
  EXPECT_LE((QuaternionLog(turn) - Eigen::Vector3d(0, report::kTotalRotationRad, 0)).norm(), 1e-12);
  EXPECT_NEAR(truth.omega_fixed.col(1).maxCoeff(), report::kPeakOmegaFixedYRadps, 1e-12);
  EXPECT_LE(truth.omega_fixed.col(0).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LE(truth.omega_fixed.col(2).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(truth.alpha_fixed.col(1).maxCoeff(), report::kPeakAlphaRadps2TwoDecimals, 0.01);
  EXPECT_NEAR(truth.acc_fixed.rowwise().norm().maxCoeff() / kStandardGravity, report::kPeakAccG, 0.005);
  // The CG stays 10 in from the axis through (0, 0, 10 in).
  for (Eigen::Index k = 0; k < truth.size(); k += 50)
    EXPECT_NEAR((truth.pos_fixed.row(k) - Eigen::RowVector3d(0, 0, 0.254)).norm(), 0.254, 1e-14);
  // A sensor at the CG along body x reads the CG acceleration in g.
  EXPECT_NEAR(test.signals.samples(300, 0) * kStandardGravity,
              test.truth.acc_body(300, 0) +
                  (test.truth.alpha_body.row(300).cross(test.array.sensors[0].position_body_m.transpose()) +
                   test.truth.omega_body.row(300).cross(test.truth.omega_body.row(300).cross(
                       test.array.sensors[0].position_body_m.transpose())))(0),
              1e-9);
}

TEST(Synth, SequentialEndsAtThreeBodyTurns) {
  const synth::SyntheticTest test = synth::SynthSequential(test_support::Ideal3222());
  const Kinematics& truth = test.truth;
  ASSERT_EQ(truth.size(), 1501);
  const Eigen::Matrix3d final_r = QuatAt(truth.quat_fixed_from_body, truth.size() - 1).toRotationMatrix();
  const double quarter = report::kSequentialTurnRad;
  EXPECT_LE((final_r - Rx(quarter) * Ry(quarter) * Rz(quarter)).norm(), 1e-12);
  // Equivalent to turns about fixed X, then fixed Z, then fixed X (report 4.4).
  EXPECT_LE((final_r - Rx(quarter) * Rz(quarter) * Rx(quarter)).norm(), 1e-12);
  // At the turn boundaries the angular acceleration jumps; elsewhere the truth is smooth.
  EXPECT_EQ(truth.vel_fixed.norm(), 0.0);
  EXPECT_NEAR(truth.omega_body.rowwise().norm().maxCoeff(), 0.25 * std::numbers::pi * std::numbers::pi / 0.04,
              1e-9);
}

TEST(Synth, RandomMotionIsSeededSmoothAndStartsAtRest) {
  synth::RandomMotionOptions options;
  options.seed = 11;
  const synth::SyntheticTest a = synth::SynthRandomMotion(test_support::VolpeTable42(), options);
  const synth::SyntheticTest b = synth::SynthRandomMotion(test_support::VolpeTable42(), options);
  options.seed = 12;
  const synth::SyntheticTest c = synth::SynthRandomMotion(test_support::VolpeTable42(), options);
  EXPECT_EQ(a.signals.samples, b.signals.samples);
  EXPECT_NE(a.signals.samples, c.signals.samples);
  ASSERT_EQ(a.truth.size(), 2001);
  ExpectSelfConsistent(a, 2e-4);
  EXPECT_EQ(a.truth.omega_body.row(0).norm(), 0.0);
  EXPECT_EQ(a.truth.alpha_body.row(0).norm(), 0.0);
  EXPECT_GT(a.initial.velocity_fixed_mps.norm(), 0.1);
  EXPECT_GT(a.initial.orientation_rad.norm(), 0.01);
  // Peaks of the order asked for.
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    options.seed = seed;
    const synth::SyntheticTest t = synth::SynthRandomMotion(test_support::Ideal3222(), options);
    const double peak_omega = t.truth.omega_body.rowwise().norm().maxCoeff();
    const double peak_acc_g = t.truth.acc_fixed.rowwise().norm().maxCoeff() / kStandardGravity;
    EXPECT_GT(peak_omega, 0.3 * options.peak_omega_radps);
    EXPECT_LT(peak_omega, 1.4 * options.peak_omega_radps);
    EXPECT_GT(peak_acc_g, 0.3 * options.peak_acc_g);
    EXPECT_LT(peak_acc_g, 1.4 * options.peak_acc_g);
  }
  options.random_initial_orientation = false;
  options.random_initial_velocity = false;
  const synth::SyntheticTest still = synth::SynthRandomMotion(test_support::Ideal3222(), options);
  EXPECT_EQ(still.initial.orientation_rad.norm(), 0.0);
  EXPECT_EQ(still.initial.velocity_fixed_mps.norm(), 0.0);
}

TEST(Synth, SignalsUseEachSlotsUnit) {
  ArrayGeometry array = test_support::NapArs12();
  array.sensors[10].unit = "deg/s";
  array.sensors[10].si_per_unit = std::numbers::pi / 180.0;
  array.sensors[0].unit = "m/s^2";
  array.sensors[0].si_per_unit = 1.0;
  synth::RandomMotionOptions options;
  const synth::SyntheticTest test = synth::SynthRandomMotion(array, options);
  for (Eigen::Index k : {0, 700, 1500}) {
    EXPECT_NEAR(test.signals.samples(k, 10), test.truth.omega_body(k, 1) * 180.0 / std::numbers::pi, 1e-9);
    EXPECT_NEAR(test.signals.samples(k, 9), test.truth.omega_body(k, 0), 1e-12);
  }
  // Linear channels: the rigid-body model at each sensor, in its unit.
  for (std::size_t i = 0; i < 9; ++i) {
    const Sensor& s = test.array.sensors[i];
    const Eigen::Index k = 1234;
    const Eigen::Vector3d w = test.truth.omega_body.row(k).transpose(),
                          al = test.truth.alpha_body.row(k).transpose();
    const Eigen::Vector3d a = test.truth.acc_body.row(k).transpose();
    const double expected =
        s.axis_body.dot(a + al.cross(s.position_body_m) + w.cross(w.cross(s.position_body_m))) /
        s.si_per_unit;
    EXPECT_NEAR(test.signals.samples(k, static_cast<Eigen::Index>(i)), expected, 1e-9) << s.slot;
  }
}

TEST(Synth, GravityReadingIsZeroedAtStartAndFollowsTheHeadTurn) {
  synth::SynthOptions with_gravity;
  with_gravity.gravity = true;
  const synth::SyntheticTest plain =
      synth::SynthSeedFixedAxis(test_support::Ideal3222(), Eigen::Vector3d(0.5, 0.5, 0.5));
  const synth::SyntheticTest heavy =
      synth::SynthSeedFixedAxis(test_support::Ideal3222(), Eigen::Vector3d(0.5, 0.5, 0.5), with_gravity);
  EXPECT_LE((plain.signals.samples.row(0) - heavy.signals.samples.row(0)).norm(), 1e-15);
  // Truth is the same motion; only the readings differ, by -(R^T - R0^T) g.
  EXPECT_EQ(plain.truth.acc_body, heavy.truth.acc_body);
  const Eigen::Index k = 1000;
  const Eigen::Matrix3d r = QuatAt(plain.truth.quat_fixed_from_body, k).toRotationMatrix();
  const Eigen::Matrix3d r0 = QuatAt(plain.truth.quat_fixed_from_body, 0).toRotationMatrix();
  const Eigen::Vector3d reading = -(r.transpose() - r0.transpose()) * Eigen::Vector3d(0, 0, kStandardGravity);
  EXPECT_NEAR((heavy.signals.samples(k, 0) - plain.signals.samples(k, 0)) * kStandardGravity, reading.x(),
              1e-9);
  EXPECT_GT(std::abs(reading.x()), 1.0);  // the test is not vacuous
}

// The padding series' head impact without noise: a free rigid head hit off
// its CG (docs/algorithms.md "Synthetic padding series").
synth::HeadImpact QuietNominalImpact() {
  synth::HeadImpact impact;
  impact.contact_point_body_m = synth::NominalContactPoint(impact.trajectory_deg);
  impact.noise_g = 0.0;
  impact.noise_radps = 0.0;
  return impact;
}

TEST(Synth, HeadImpactTruthIsAnExactRigidBodyPushedOffItsCg) {
  const synth::HeadImpact impact = QuietNominalImpact();
  const synth::SyntheticTest test = synth::SynthHeadImpact(test_support::Ideal3222(), impact);
  const Kinematics& truth = test.truth;
  ASSERT_EQ(truth.size(), 1001);  // 100 ms at 10 kHz
  ExpectSelfConsistent(test, 2e-4);
  const double dt = test.signals.dt_s;

  // The CG: a haversine pulse of impulse (1 + e) v against the trajectory,
  // from contact_start_s for pulse_s; rebound at e v.
  const double trajectory = impact.trajectory_deg / kDegPerRad;
  const Eigen::Vector3d u(std::cos(trajectory), -std::sin(trajectory), 0.0);
  EXPECT_LE((test.initial.velocity_fixed_mps - impact.speed_mps * u).norm(), 1e-12);
  const double peak = 2.0 * (1.0 + impact.restitution) * impact.speed_mps / impact.pulse_s;
  for (Eigen::Index k = 0; k < truth.size(); ++k) {
    const double tau = (truth.time_s(k) - impact.contact_start_s) / impact.pulse_s;
    const double expected =
        (tau > 0.0 && tau < 1.0) ? peak * std::pow(std::sin(std::numbers::pi * tau), 2) : 0.0;
    ASSERT_NEAR(truth.acc_fixed.row(k).dot(-u), expected, 1e-9 * peak) << k;
    ASSERT_LE(truth.acc_fixed.row(k).cross(u.transpose()).norm(), 1e-9 * peak) << k;
  }
  EXPECT_LE(
      (truth.vel_fixed.row(truth.size() - 1).transpose() + impact.restitution * impact.speed_mps * u).norm(),
      1e-12);

  // Angular momentum about the CG, H = R I w (fixed axes), changes by the
  // impulse of the padding force's moment (R r_c) x F plus the neck's,
  // recomputed from the truth by the trapezoid rule.
  const Eigen::Matrix3d inertia = impact.head_inertia_kgm2.asDiagonal();
  auto momentum = [&](Eigen::Index k) -> Eigen::Vector3d {
    return QuatAt(truth.quat_fixed_from_body, k) * (inertia * truth.omega_body.row(k).transpose());
  };
  auto torque = [&](Eigen::Index k) -> Eigen::Vector3d {
    const Eigen::Quaterniond q = QuatAt(truth.quat_fixed_from_body, k);
    const Eigen::Vector3d force = impact.head_mass_kg * truth.acc_fixed.row(k).transpose();
    const Eigen::Vector3d neck_body = -impact.neck_stiffness_nm_per_rad * QuaternionLog(q) -
                                      impact.neck_damping_nms_per_rad * truth.omega_body.row(k).transpose();
    return (q * impact.contact_point_body_m).cross(force) + q * neck_body;
  };
  Eigen::Vector3d impulse = Eigen::Vector3d::Zero();
  double worst = 0.0, scale = 0.0;
  for (Eigen::Index k = 1; k < truth.size(); ++k) {
    impulse += 0.5 * dt * (torque(k - 1) + torque(k));
    worst = std::max(worst, (momentum(k) - momentum(0) - impulse).norm());
    scale = std::max(scale, (momentum(k) - momentum(0)).norm());
  }
  EXPECT_LE(worst, 2e-4 * scale);

  // An oblique contact turns the head about all three axes, at a rate of
  // the order crash tests show.
  const double peak_omega = truth.omega_body.rowwise().norm().maxCoeff();
  EXPECT_GT(peak_omega, 15.0);
  EXPECT_LT(peak_omega, 50.0);
  for (int axis = 0; axis < 3; ++axis)
    EXPECT_GT(truth.omega_body.col(axis).cwiseAbs().maxCoeff(), 1.0) << axis;
  EXPECT_EQ(truth.omega_body.row(0).norm(), 0.0);
}

TEST(Synth, HeadImpactNoiseIsSeededAndStaysOutOfTheTruth) {
  const synth::HeadImpact quiet = QuietNominalImpact();
  synth::HeadImpact noisy = quiet;
  noisy.noise_g = 0.2;
  noisy.noise_seed = 21;
  const ArrayGeometry array = test_support::Ideal3222();
  const synth::SyntheticTest clean = synth::SynthHeadImpact(array, quiet);
  const synth::SyntheticTest a = synth::SynthHeadImpact(array, noisy);
  const synth::SyntheticTest b = synth::SynthHeadImpact(array, noisy);
  noisy.noise_seed = 22;
  const synth::SyntheticTest c = synth::SynthHeadImpact(array, noisy);
  EXPECT_EQ(a.signals.samples, b.signals.samples);
  EXPECT_NE(a.signals.samples, c.signals.samples);
  EXPECT_EQ(a.truth.omega_body, clean.truth.omega_body);
  EXPECT_EQ(a.truth.acc_fixed, clean.truth.acc_fixed);
  EXPECT_EQ(a.truth.quat_fixed_from_body, clean.truth.quat_fixed_from_body);
  // White noise of the asked RMS (in g) on every linear channel.
  for (Eigen::Index i = 0; i < a.signals.samples.cols(); ++i) {
    const Eigen::VectorXd noise = a.signals.samples.col(i) - clean.signals.samples.col(i);
    const double mean = noise.mean();
    const double rms = std::sqrt((noise.array() - mean).square().mean());
    EXPECT_NEAR(rms, 0.2, 0.02) << i;
    EXPECT_LT(std::abs(mean), 0.03) << i;
  }
}

TEST(Synth, DisplaceSensorsMovesEverySensorWithinTheBound) {
  const ArrayGeometry nominal = test_support::Denton3222();
  const double bound = 0.25 * kMetresPerInch;
  const ArrayGeometry a = synth::DisplaceSensors(nominal, bound, 5);
  const ArrayGeometry b = synth::DisplaceSensors(nominal, bound, 5);
  const ArrayGeometry c = synth::DisplaceSensors(nominal, bound, 6);
  double largest = 0.0;
  for (std::size_t i = 0; i < nominal.sensors.size(); ++i) {
    const double offset = (a.sensors[i].position_body_m - nominal.sensors[i].position_body_m).norm();
    EXPECT_LE(offset, bound);
    EXPECT_GT(offset, 0.0);
    largest = std::max(largest, offset);
    EXPECT_EQ(a.sensors[i].position_body_m, b.sensors[i].position_body_m);
    EXPECT_NE(a.sensors[i].position_body_m, c.sensors[i].position_body_m);
    EXPECT_EQ(a.sensors[i].axis_body, nominal.sensors[i].axis_body);
  }
  EXPECT_GT(largest, 0.3 * bound);
}

}  // namespace
}  // namespace napkin::engine
