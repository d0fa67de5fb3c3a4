// SO(3) properties (Sophus/manif style): exp/log round trips at awkward
// angles, integration of known motions against closed forms, full-range
// roll/pitch/yaw.
#include "engine/rotation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "engine/integration.h"
#include "engine/units.h"

namespace napkin::engine {
namespace {

double MatrixAngle(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  // Independent of the quaternion code, accurate for small angles: the
  // skew part of a^T b is sin(angle) times the axis (angles below 90 deg).
  const Eigen::Matrix3d m = a.transpose() * b;
  const Eigen::Vector3d v(m(2, 1) - m(1, 2), m(0, 2) - m(2, 0), m(1, 0) - m(0, 1));
  return std::asin(std::min(1.0, 0.5 * v.norm()));
}

TEST(Rotation, ExpLogRoundTripAtAwkwardAngles) {
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  for (double angle :
       {0.0, 1e-12, 1e-8, 1e-5, 1e-4, 0.5, 1.0, 3.0, std::numbers::pi - 1e-6, std::numbers::pi - 1e-9}) {
    SCOPED_TRACE(angle);
    const Eigen::Vector3d v = angle * axis;
    const Eigen::Quaterniond q = QuaternionExp(v);
    EXPECT_NEAR(q.norm(), 1.0, 1e-15);
    const Eigen::Vector3d back = QuaternionLog(q);
    EXPECT_LE((back - v).norm(), 1e-14 + 1e-12 * angle);
    // Against the matrix exponential (Rodrigues), computed independently.
    const Eigen::Matrix3d rodrigues = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
    EXPECT_LE((q.toRotationMatrix() - rodrigues).norm(), 1e-15 + 1e-15 * angle);
  }
  // exp(log(q)) = q for random unit quaternions (either sign of q).
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    Eigen::Quaterniond q(u(random), u(random), u(random), u(random));
    q.normalize();
    const Eigen::Quaterniond back = QuaternionExp(QuaternionLog(q));
    EXPECT_NEAR(std::abs(back.coeffs().dot(q.coeffs())), 1.0, 1e-14);
  }
}

TEST(Rotation, ConstantOmegaIntegrationEqualsClosedForm) {
  const double dt = 1e-4;
  const Eigen::Index n = 2001;
  const Eigen::Vector3d omega(12.0, -31.0, 7.5);
  Series3 omega_body(n, 3), alpha_body = Series3::Zero(n, 3);
  omega_body.rowwise() = omega.transpose();
  const Eigen::Quaterniond q0(InitialFixedFromBody(Eigen::Vector3d(0.5, -1.0, 2.0)));
  Series4 quat;
  IntegrateOrientation(dt, omega_body, alpha_body, q0, quat);
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Matrix3d closed =
        q0.toRotationMatrix() *
        Eigen::AngleAxisd(omega.norm() * dt * static_cast<double>(k), omega.normalized()).toRotationMatrix();
    ASSERT_LE(MatrixAngle(QuatAt(quat, k).toRotationMatrix(), closed), 1e-11) << k;
    ASSERT_NEAR(QuatAt(quat, k).norm(), 1.0, 1e-14);
  }
}

// R(t) = Rz(a t) Rx(b t): body omega = (b, a sin bt, a cos bt) cones about
// body x. The coning-corrected integrator converges at fourth order.
TEST(Rotation, ConingMotionIntegrationConvergesToClosedForm) {
  const double a = 25.0, b = 40.0, duration = 0.2;
  double previous_error = 0.0;
  for (double dt : {4e-4, 2e-4, 1e-4}) {
    const auto n = static_cast<Eigen::Index>(std::llround(duration / dt)) + 1;
    Series3 omega(n, 3), alpha(n, 3);
    for (Eigen::Index k = 0; k < n; ++k) {
      const double t = dt * static_cast<double>(k);
      omega.row(k) << b, a * std::sin(b * t), a * std::cos(b * t);
      alpha.row(k) << 0.0, a * b * std::cos(b * t), -a * b * std::sin(b * t);
    }
    Series4 quat;
    IntegrateOrientation(dt, omega, alpha, Eigen::Quaterniond::Identity(), quat);
    double error = 0.0;
    for (Eigen::Index k = 0; k < n; ++k) {
      const double t = dt * static_cast<double>(k);
      error = std::max(error, MatrixAngle(QuatAt(quat, k).toRotationMatrix(), Rz(a * t) * Rx(b * t)));
    }
    std::printf("[errors] coning dt %.0e: max orientation error %.3e deg\n", dt, error * kDegPerRad);
    if (previous_error > 0.0) {
      EXPECT_LT(error, previous_error / 12.0);  // fourth order
    }
    previous_error = error;
  }
  EXPECT_LT(previous_error * kDegPerRad, 1e-8);
}

TEST(Rotation, RollPitchYawRoundTripOverFullRange) {
  const double near_lock = std::numbers::pi / 2 - 1e-7;
  for (double roll : {-std::numbers::pi + 1e-9, -2.5, -1.0, 0.0, 0.3, 1.7, 3.0, std::numbers::pi}) {
    for (double pitch : {-near_lock, -1.2, -0.4, 0.0, 0.6, 1.5, near_lock}) {
      for (double yaw : {-3.1, -1.5, 0.0, 0.9, 2.8, std::numbers::pi}) {
        const Eigen::Matrix3d r = Rz(yaw) * Ry(pitch) * Rx(roll);
        const Eigen::Vector3d angles = RollPitchYaw(r);
        const Eigen::Matrix3d back = Rz(angles.z()) * Ry(angles.y()) * Rx(angles.x());
        EXPECT_LE((back - r).norm(), 1e-12);
        EXPECT_NEAR(angles.y(), pitch, 1e-8);
        // Angles themselves, modulo 2 pi (roll = pi and -pi are the same).
        EXPECT_NEAR(std::remainder(angles.x() - roll, 2 * std::numbers::pi), 0.0, 2e-7);
        EXPECT_NEAR(std::remainder(angles.z() - yaw, 2 * std::numbers::pi), 0.0, 2e-7);
      }
    }
  }
  // Exactly at gimbal lock only yaw -/+ roll is defined: R must still round-trip.
  for (double pitch : {std::numbers::pi / 2, -std::numbers::pi / 2}) {
    const Eigen::Matrix3d r = Rz(0.7) * Ry(pitch) * Rx(-0.4);
    const Eigen::Vector3d angles = RollPitchYaw(r);
    EXPECT_LE((Rz(angles.z()) * Ry(angles.y()) * Rx(angles.x()) - r).norm(), 1e-12);
  }
}

TEST(Rotation, DirectionCosineAnglesAreAnglesBetweenBodyAndFixedAxes) {
  const Eigen::Matrix3d r = Rx(0.4) * Ry(-0.3) * Rz(1.1);
  const Eigen::Vector3d angles = DirectionCosineAngles(r);
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d body_axis_in_fixed = r * Eigen::Vector3d::Unit(i);
    EXPECT_NEAR(angles[i], std::acos(body_axis_in_fixed.dot(Eigen::Vector3d::Unit(i))), 1e-14);
  }
  EXPECT_NEAR(DirectionCosineAngles(Rx(std::numbers::pi / 2)).y(), std::numbers::pi / 2, 1e-15);
}

}  // namespace
}  // namespace napkin::engine
