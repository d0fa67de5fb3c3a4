#pragma once
// The angle series of an orientation series (docs/algorithms.md
// "Orientation"): roll/pitch/yaw with R = Rz(yaw) Ry(pitch) Rx(roll) via
// atan2 and the direction-cosine angles acos(diag R), for every sample of a
// unit quaternion series, in one loop that uses SIMD atan2 and acos where
// the processor has them.
#include <Eigen/Core>
#include <atomic>

#include "engine/kinematics.h"

namespace napkin::engine {

// q.toRotationMatrix() of the unit quaternion (w, x, y, z), term for term,
// from scalars (the rotation of every per-sample series of the solvers).
inline Eigen::Matrix3d RotationMatrixOfUnitQuaternion(double qw, double qx, double qy, double qz) {
  const double tx = 2.0 * qx, ty = 2.0 * qy, tz = 2.0 * qz;
  const double twx = tx * qw, twy = ty * qw, twz = tz * qw;
  const double txx = tx * qx, txy = ty * qx, txz = tz * qx;
  const double tyy = ty * qy, tyz = tz * qy, tzz = tz * qz;
  Eigen::Matrix3d r;
  r << 1.0 - (tyy + tzz), txy - twz, txz + twy, txy + twz, 1.0 - (txx + tzz), tyz - twx, txz - twy, tyz + twx,
      1.0 - (txx + tyy);
  return r;
}

// How OrientationAngles computes the angles.
enum class AnglesImplementation {
  kScalar,  // RollPitchYaw and DirectionCosineAngles (engine/rotation.h) sample by sample
  kAvx2,    // x86-64 with AVX2 and FMA: glibc's libmvec atan2/acos, four samples at a time
  kAvx512,  // x86-64 with AVX-512 F and DQ: the same, eight samples at a time
};

// The fastest implementation this processor and build support.
AnglesImplementation BestAnglesImplementation();

// roll_pitch_yaw_rad.row(k) = RollPitchYaw(R_k) and dcos_rad.row(k) =
// DirectionCosineAngles(R_k) with R_k = RotationMatrixOfUnitQuaternion of
// row k of quat_fixed_from_body (w, x, y, z); the outputs are resized to its
// rows. The vectorized implementation's atan2 and acos are accurate to a few
// ulp (libm's to one): the angles equal the scalar ones within round-off,
// with the same gimbal-lock branch, clamping and NaN propagation. An
// implementation this processor or build lacks falls back to the best one
// below it that it has (kAvx512 -> kAvx2 -> kScalar). Throws Cancelled once
// `cancel` is set (engine/cancellation.h).
void OrientationAngles(const Series4& quat_fixed_from_body, Series3& roll_pitch_yaw_rad, Series3& dcos_rad,
                       AnglesImplementation implementation = BestAnglesImplementation(),
                       const std::atomic<bool>* cancel = nullptr);

}  // namespace napkin::engine
