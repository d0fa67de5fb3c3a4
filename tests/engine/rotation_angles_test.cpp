// The angle series (engine/rotation_angles.h): every implementation equals
// RollPitchYaw and DirectionCosineAngles (engine/rotation.h) of each row's
// rotation matrix, the scalar one bit for bit, the vectorized (libmvec) one
// within a few ulp, on random rotations and on the awkward ones (identity,
// gimbal lock, half turns, NaN, arguments of acos just outside [-1, 1]),
// for lengths that are and are not multiples of the vector width.
#include "engine/rotation_angles.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "engine/rotation.h"
#include "engine/units.h"
#include "tests/support/ulp_distance.h"

namespace napkin::engine {
namespace {

using test_support::UlpDistance;

Eigen::Quaterniond Quaternion(const Eigen::Matrix3d& r) { return Eigen::Quaterniond(r).normalized(); }

// Random unit quaternions, with the awkward rotations scattered among them
// (so that they fall in every lane of a vector block).
Series4 TestQuaternions(Eigen::Index n) {
  std::vector<Eigen::Quaterniond> awkward = {
      Eigen::Quaterniond::Identity(),
      Eigen::Quaterniond(-1.0, 0.0, 0.0, 0.0),  // identity, other hemisphere
      Quaternion(Ry(std::numbers::pi / 2)),     // pitch +90 deg: gimbal lock
      Quaternion(Ry(-std::numbers::pi / 2)),    // pitch -90 deg: gimbal lock
      Quaternion(Rz(0.7) * Ry(std::numbers::pi / 2) * Rx(-0.4)),
      Quaternion(Rz(-2.9) * Ry(-std::numbers::pi / 2) * Rx(1.3)),
      Quaternion(Rz(0.3) * Ry(std::numbers::pi / 2 - 1e-9) * Rx(0.2)),  // near, not at, gimbal lock
      Eigen::Quaterniond(0.0, 1.0, 0.0, 0.0),                           // half turns about x, y, z
      Eigen::Quaterniond(0.0, 0.0, 1.0, 0.0),
      Eigen::Quaterniond(0.0, 0.0, 0.0, 1.0),
      Eigen::Quaterniond(0.0, std::sqrt(0.5), std::sqrt(0.5), 0.0),  // half turn about (1, 1, 0)
      Quaternion(Rz(std::numbers::pi) * Ry(0.3) * Rx(-std::numbers::pi)),
      Eigen::Quaterniond(1.0 + 1e-15, 1e-9, -1e-9, 2e-9),  // slightly long: diagonal of R near 1
      Eigen::Quaterniond(1e-17, 1.0 + 1e-15, 0.0, 0.0),    // R(1,1), R(2,2) below -1: clamped
      Eigen::Quaterniond(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0, 0.0),
      Eigen::Quaterniond(0.5, std::numeric_limits<double>::quiet_NaN(), 0.5, 0.5),
  };
  std::mt19937_64 random(12);
  std::normal_distribution<double> normal;
  Series4 quat(n, 4);
  for (Eigen::Index k = 0; k < n; ++k) {
    Eigen::Quaterniond q;
    if (k % 5 == 3 && !awkward.empty()) {
      q = awkward.back();
      awkward.pop_back();
    } else {
      q = Eigen::Quaterniond(normal(random), normal(random), normal(random), normal(random)).normalized();
    }
    quat.row(k) << q.w(), q.x(), q.y(), q.z();
  }
  return quat;
}

// kScalar and every vectorized implementation this processor and build have.
std::vector<AnglesImplementation> SupportedImplementations() {
  std::vector<AnglesImplementation> supported;
  for (AnglesImplementation implementation :
       {AnglesImplementation::kScalar, AnglesImplementation::kAvx2, AnglesImplementation::kAvx512})
    if (static_cast<int>(implementation) <= static_cast<int>(BestAnglesImplementation()))
      supported.push_back(implementation);
  return supported;
}

// Max ulp distance of the angles from the scalar functions, row by row.
std::uint64_t MaxUlpFromScalarFunctions(const Series4& quat, AnglesImplementation implementation) {
  Series3 roll_pitch_yaw, dcos;
  OrientationAngles(quat, roll_pitch_yaw, dcos, implementation);
  EXPECT_EQ(roll_pitch_yaw.rows(), quat.rows());
  EXPECT_EQ(dcos.rows(), quat.rows());
  std::uint64_t max_ulp = 0;
  for (Eigen::Index k = 0; k < quat.rows(); ++k) {
    const Eigen::Matrix3d r = RotationMatrixOfUnitQuaternion(quat(k, 0), quat(k, 1), quat(k, 2), quat(k, 3));
    const Eigen::Vector3d expected_roll_pitch_yaw = RollPitchYaw(r), expected_dcos = DirectionCosineAngles(r);
    for (int i = 0; i < 3; ++i) {
      SCOPED_TRACE(testing::Message() << "row " << k << " angle " << i);
      const std::uint64_t ulp_rpy = UlpDistance(roll_pitch_yaw(k, i), expected_roll_pitch_yaw(i));
      const std::uint64_t ulp_dcos = UlpDistance(dcos(k, i), expected_dcos(i));
      EXPECT_LE(ulp_rpy, 4u) << roll_pitch_yaw(k, i) << " vs " << expected_roll_pitch_yaw(i);
      EXPECT_LE(ulp_dcos, 4u) << dcos(k, i) << " vs " << expected_dcos(i);
      max_ulp = std::max({max_ulp, ulp_rpy, ulp_dcos});
    }
  }
  return max_ulp;
}

TEST(RotationAngles, AwkwardRotationsHaveTheExpectedScalarAngles) {
  // Every implementation on the awkward cases: gimbal lock puts yaw - roll
  // in yaw, the clamp keeps acos finite, NaN stays NaN.
  Series4 quat(4, 4);
  const Eigen::Quaterniond locked = Quaternion(Rz(0.7) * Ry(std::numbers::pi / 2) * Rx(-0.4));
  quat.row(0) << locked.w(), locked.x(), locked.y(), locked.z();
  quat.row(1) << 1e-17, 1.0 + 1e-15, 0.0, 0.0;  // |q| > 1: R(1,1) = R(2,2) = -1 - 4e-15
  quat.row(2).setConstant(std::numeric_limits<double>::quiet_NaN());
  quat.row(3) << 0.0, 0.0, 0.0, 1.0;
  for (AnglesImplementation implementation : SupportedImplementations()) {
    SCOPED_TRACE(static_cast<int>(implementation));
    Series3 roll_pitch_yaw, dcos;
    OrientationAngles(quat, roll_pitch_yaw, dcos, implementation);
    EXPECT_EQ(roll_pitch_yaw(0, 0), 0.0);
    EXPECT_NEAR(roll_pitch_yaw(0, 1), std::numbers::pi / 2, 2e-8);  // sqrt of round-off near the pole
    EXPECT_NEAR(roll_pitch_yaw(0, 2), 0.7 + 0.4, 1e-8);
    EXPECT_NEAR(dcos(1, 0), 0.0, 1e-7);
    EXPECT_NEAR(dcos(1, 1), std::numbers::pi, 1e-15);
    EXPECT_NEAR(dcos(1, 2), std::numbers::pi, 1e-15);
    for (int i = 0; i < 3; ++i) {
      EXPECT_TRUE(std::isnan(roll_pitch_yaw(2, i)));
      EXPECT_TRUE(std::isnan(dcos(2, i)));
    }
    EXPECT_NEAR(std::abs(roll_pitch_yaw(3, 2)), std::numbers::pi, 1e-15);  // half turn about z
    EXPECT_NEAR(dcos(3, 0), std::numbers::pi, 1e-15);
    EXPECT_NEAR(dcos(3, 2), 0.0, 1e-15);
  }
}

TEST(RotationAngles, ScalarImplementationIsRollPitchYawAndDirectionCosineAnglesExactly) {
  const Series4 quat = TestQuaternions(1003);
  EXPECT_EQ(MaxUlpFromScalarFunctions(quat, AnglesImplementation::kScalar), 0u);
}

TEST(RotationAngles, VectorizedImplementationsEqualScalarFunctionsWithinFourUlp) {
  if (BestAnglesImplementation() == AnglesImplementation::kScalar)
    GTEST_SKIP() << "no vectorized implementation on this processor or build (scalar only)";
  // 10,003 rows: many random rotations, the awkward ones in every lane, and
  // a tail shorter than the vector width.
  const Series4 quat = TestQuaternions(10003);
  for (AnglesImplementation implementation : SupportedImplementations()) {
    if (implementation == AnglesImplementation::kScalar) continue;
    SCOPED_TRACE(static_cast<int>(implementation));
    const std::uint64_t max_ulp = MaxUlpFromScalarFunctions(quat, implementation);
    RecordProperty("max_ulp_" + std::to_string(static_cast<int>(implementation)), static_cast<int>(max_ulp));
    EXPECT_LE(max_ulp, 4u);
  }
}

TEST(RotationAngles, EveryLengthIncludingTailsShorterThanAVector) {
  for (Eigen::Index n = 0; n <= 19; ++n) {
    SCOPED_TRACE(n);
    const Series4 quat = TestQuaternions(n);
    EXPECT_EQ(MaxUlpFromScalarFunctions(quat, AnglesImplementation::kScalar), 0u);
    for (AnglesImplementation implementation : SupportedImplementations())
      EXPECT_LE(MaxUlpFromScalarFunctions(quat, implementation), 4u);
  }
}

}  // namespace
}  // namespace napkin::engine
