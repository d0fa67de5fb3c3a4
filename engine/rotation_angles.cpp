#include "engine/rotation_angles.h"

#include <algorithm>

#include "engine/cancellation.h"
#include "engine/rotation.h"
#include "engine/rotation_angles_lanes.h"

// The vectorized loops (engine/rotation_angles_lanes.h) need x86-64 and
// glibc's libmvec with the AVX2 and AVX-512 atan2 and acos (glibc >= 2.35);
// engine/CMakeLists.txt defines NAPKIN_HAVE_LIBMVEC_AVX2 when the build links them.
#if defined(NAPKIN_HAVE_LIBMVEC_AVX2) && defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define NAPKIN_ANGLES_AVX2 1
#else
#define NAPKIN_ANGLES_AVX2 0
#endif

namespace napkin::engine {

void internal::ScalarAngleRows(const AngleColumns& columns, std::ptrdiff_t begin, std::ptrdiff_t end) {
  for (std::ptrdiff_t k = begin; k < end; ++k) {
    const Eigen::Matrix3d r =
        RotationMatrixOfUnitQuaternion(columns.qw[k], columns.qx[k], columns.qy[k], columns.qz[k]);
    const Eigen::Vector3d angles = RollPitchYaw(r);
    const Eigen::Vector3d direction_cosine_angles = DirectionCosineAngles(r);
    columns.roll[k] = angles(0);
    columns.pitch[k] = angles(1);
    columns.yaw[k] = angles(2);
    for (int i = 0; i < 3; ++i) columns.dcos[i][k] = direction_cosine_angles(i);
  }
}

namespace {

#if NAPKIN_ANGLES_AVX2
bool ProcessorHasAvx2() {
  static const bool kHasAvx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return kHasAvx2;
}

// libmvec's AVX-512 functions need AVX512DQ as well (else they fall back to AVX2 code).
bool ProcessorHasAvx512() {
  static const bool kHasAvx512 =
      ProcessorHasAvx2() && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq");
  return kHasAvx512;
}
#endif

}  // namespace

AnglesImplementation BestAnglesImplementation() {
#if NAPKIN_ANGLES_AVX2
  if (ProcessorHasAvx512()) return AnglesImplementation::kAvx512;
  if (ProcessorHasAvx2()) return AnglesImplementation::kAvx2;
#endif
  return AnglesImplementation::kScalar;
}

void OrientationAngles(const Series4& quat_fixed_from_body, Series3& roll_pitch_yaw_rad, Series3& dcos_rad,
                       AnglesImplementation implementation, const std::atomic<bool>* cancel) {
  const Eigen::Index n = quat_fixed_from_body.rows();
  roll_pitch_yaw_rad.resize(n, 3);
  dcos_rad.resize(n, 3);
  // In blocks of rows, looking at `cancel` between two (a long record's
  // angles take most of a second); each block a multiple of the eight lanes,
  // so that the samples left to the scalar loop are those of the last block
  // only, as in one pass.
  constexpr Eigen::Index kBlockRows = 8 * kCancellationStride;
  for (Eigen::Index begin = 0; begin < n; begin += kBlockRows) {
    ThrowIfCancelled(cancel);
    const Eigen::Index rows = std::min(kBlockRows, n - begin);
    const internal::AngleColumns columns{
        rows,
        quat_fixed_from_body.col(0).data() + begin,
        quat_fixed_from_body.col(1).data() + begin,
        quat_fixed_from_body.col(2).data() + begin,
        quat_fixed_from_body.col(3).data() + begin,
        roll_pitch_yaw_rad.col(0).data() + begin,
        roll_pitch_yaw_rad.col(1).data() + begin,
        roll_pitch_yaw_rad.col(2).data() + begin,
        {dcos_rad.col(0).data() + begin, dcos_rad.col(1).data() + begin, dcos_rad.col(2).data() + begin}};
    std::ptrdiff_t done = 0;
#if NAPKIN_ANGLES_AVX2
    // Per-sample atan2 and acos were about 30 % of the exact solver's time
    // (perf); libmvec computes four (eight) of each in about the time of one.
    if (implementation == AnglesImplementation::kAvx512 && ProcessorHasAvx512())
      done = internal::Avx512AngleRows(columns);
    else if (implementation != AnglesImplementation::kScalar && ProcessorHasAvx2())
      done = internal::Avx2AngleRows(columns);
#else
    (void)implementation;
#endif
    internal::ScalarAngleRows(columns, done, rows);
  }
}

}  // namespace napkin::engine
