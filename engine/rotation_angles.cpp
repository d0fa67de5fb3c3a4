#include "engine/rotation_angles.h"

#include "engine/rotation.h"

// The vectorized loops need x86-64 and glibc's libmvec with the AVX2 and
// AVX-512 atan2 and acos (glibc >= 2.35); engine/CMakeLists.txt defines
// NAPKIN_HAVE_LIBMVEC_AVX2 when the build links them.
#if defined(NAPKIN_HAVE_LIBMVEC_AVX2) && defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define NAPKIN_ANGLES_AVX2 1
#include <immintrin.h>

#define NAPKIN_TARGET_AVX2 __attribute__((target("avx2,fma")))
#define NAPKIN_TARGET_AVX512 __attribute__((target("avx512f,avx512dq,avx2,fma")))

// glibc's libmvec (vector function ABI, "d" = AVX2, 4 lanes, "e" = AVX-512,
// 8 lanes): atan2(y, x) and acos(x) of each lane, to within a few ulp of libm's.
NAPKIN_TARGET_AVX2 __m256d NapkinAtan2x4(__m256d y, __m256d x) __asm__("_ZGVdN4vv_atan2");
NAPKIN_TARGET_AVX2 __m256d NapkinAcosx4(__m256d x) __asm__("_ZGVdN4v_acos");
NAPKIN_TARGET_AVX512 __m512d NapkinAtan2x8(__m512d y, __m512d x) __asm__("_ZGVeN8vv_atan2");
NAPKIN_TARGET_AVX512 __m512d NapkinAcosx8(__m512d x) __asm__("_ZGVeN8v_acos");
#else
#define NAPKIN_ANGLES_AVX2 0
#endif

namespace napkin::engine {
namespace {

using Eigen::Index;

// Rows [begin, end) with engine/rotation.h's scalar functions.
void ScalarAngles(const Series4& quat, Index begin, Index end, Series3& roll_pitch_yaw, Series3& dcos) {
  for (Index k = begin; k < end; ++k) {
    const Eigen::Matrix3d r = RotationMatrixOfUnitQuaternion(quat(k, 0), quat(k, 1), quat(k, 2), quat(k, 3));
    const Eigen::Vector3d angles = RollPitchYaw(r);
    const Eigen::Vector3d direction_cosine_angles = DirectionCosineAngles(r);
    for (Index i = 0; i < 3; ++i) {
      roll_pitch_yaw(k, i) = angles(i);
      dcos(k, i) = direction_cosine_angles(i);
    }
  }
}

#if NAPKIN_ANGLES_AVX2
// std::clamp(v, -1.0, 1.0) lane by lane, NaN kept (max and min return
// their second operand when one is NaN).
NAPKIN_TARGET_AVX2 inline __m256d ClampToUnit(__m256d v) {
  return _mm256_min_pd(_mm256_set1_pd(1.0), _mm256_max_pd(_mm256_set1_pd(-1.0), v));
}

// The scalar code of engine/rotation.h four samples at a time: the same
// rotation-matrix entries, operation for operation (this file is compiled
// without floating-point contraction, so no FMA changes them), and the same
// sqrt; only atan2 and acos are libmvec's. A block with a sample at gimbal
// lock (RollPitchYaw's cos(pitch)^2 < 1e-24 branch) is done by the scalar
// code. NaN propagates as in the scalar code: a NaN quaternion fails the
// gimbal-lock test, atan2 and acos of NaN are NaN, and the clamp keeps NaN.
// Returns the number of rows done, a multiple of 4. Avx512Angles is the same
// loop eight samples at a time.
NAPKIN_TARGET_AVX2 Index Avx2Angles(const Series4& quat, Series3& roll_pitch_yaw, Series3& dcos) {
  const Index n = quat.rows();
  const double *qw = quat.col(0).data(), *qx = quat.col(1).data(), *qy = quat.col(2).data(),
               *qz = quat.col(3).data();
  double *roll = roll_pitch_yaw.col(0).data(), *pitch = roll_pitch_yaw.col(1).data(),
         *yaw = roll_pitch_yaw.col(2).data();
  double *dcos_0 = dcos.col(0).data(), *dcos_1 = dcos.col(1).data(), *dcos_2 = dcos.col(2).data();
  const __m256d one = _mm256_set1_pd(1.0), two = _mm256_set1_pd(2.0);
  const __m256d sign_bit = _mm256_set1_pd(-0.0);
  const __m256d gimbal_lock_cos_pitch_sq = _mm256_set1_pd(1e-24);
  Index k = 0;
  for (; k + 4 <= n; k += 4) {
    const __m256d w = _mm256_loadu_pd(qw + k), x = _mm256_loadu_pd(qx + k), y = _mm256_loadu_pd(qy + k),
                  z = _mm256_loadu_pd(qz + k);
    // RotationMatrixOfUnitQuaternion.
    const __m256d tx = _mm256_mul_pd(two, x), ty = _mm256_mul_pd(two, y), tz = _mm256_mul_pd(two, z);
    const __m256d twx = _mm256_mul_pd(tx, w), twy = _mm256_mul_pd(ty, w), twz = _mm256_mul_pd(tz, w);
    const __m256d txx = _mm256_mul_pd(tx, x), txy = _mm256_mul_pd(ty, x), txz = _mm256_mul_pd(tz, x);
    const __m256d tyy = _mm256_mul_pd(ty, y), tyz = _mm256_mul_pd(tz, y), tzz = _mm256_mul_pd(tz, z);
    const __m256d r00 = _mm256_sub_pd(one, _mm256_add_pd(tyy, tzz));
    const __m256d r11 = _mm256_sub_pd(one, _mm256_add_pd(txx, tzz));
    const __m256d r22 = _mm256_sub_pd(one, _mm256_add_pd(txx, tyy));
    const __m256d r10 = _mm256_add_pd(txy, twz);
    const __m256d r20 = _mm256_sub_pd(txz, twy);
    const __m256d r21 = _mm256_add_pd(tyz, twx);
    // RollPitchYaw.
    const __m256d cos_pitch_sq = _mm256_add_pd(_mm256_mul_pd(r21, r21), _mm256_mul_pd(r22, r22));
    if (_mm256_movemask_pd(_mm256_cmp_pd(cos_pitch_sq, gimbal_lock_cos_pitch_sq, _CMP_LT_OQ)) != 0) {
      ScalarAngles(quat, k, k + 4, roll_pitch_yaw, dcos);
      continue;
    }
    const __m256d cos_pitch = _mm256_sqrt_pd(_mm256_add_pd(_mm256_mul_pd(r00, r00), _mm256_mul_pd(r10, r10)));
    _mm256_storeu_pd(pitch + k, NapkinAtan2x4(_mm256_xor_pd(r20, sign_bit), cos_pitch));
    _mm256_storeu_pd(roll + k, NapkinAtan2x4(r21, r22));
    _mm256_storeu_pd(yaw + k, NapkinAtan2x4(r10, r00));
    // DirectionCosineAngles.
    _mm256_storeu_pd(dcos_0 + k, NapkinAcosx4(ClampToUnit(r00)));
    _mm256_storeu_pd(dcos_1 + k, NapkinAcosx4(ClampToUnit(r11)));
    _mm256_storeu_pd(dcos_2 + k, NapkinAcosx4(ClampToUnit(r22)));
  }
  return k;
}

// GCC 12's AVX-512 intrinsics read an undefined vector (_mm512_undefined_pd)
// that -Wmaybe-uninitialized flags (a false positive fixed in GCC 13).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
NAPKIN_TARGET_AVX512 inline __m512d ClampToUnit8(__m512d v) {
  return _mm512_min_pd(_mm512_set1_pd(1.0), _mm512_max_pd(_mm512_set1_pd(-1.0), v));
}

NAPKIN_TARGET_AVX512 Index Avx512Angles(const Series4& quat, Series3& roll_pitch_yaw, Series3& dcos) {
  const Index n = quat.rows();
  const double *qw = quat.col(0).data(), *qx = quat.col(1).data(), *qy = quat.col(2).data(),
               *qz = quat.col(3).data();
  double *roll = roll_pitch_yaw.col(0).data(), *pitch = roll_pitch_yaw.col(1).data(),
         *yaw = roll_pitch_yaw.col(2).data();
  double *dcos_0 = dcos.col(0).data(), *dcos_1 = dcos.col(1).data(), *dcos_2 = dcos.col(2).data();
  const __m512d one = _mm512_set1_pd(1.0), two = _mm512_set1_pd(2.0);
  const __m512d sign_bit = _mm512_set1_pd(-0.0);
  const __m512d gimbal_lock_cos_pitch_sq = _mm512_set1_pd(1e-24);
  Index k = 0;
  for (; k + 8 <= n; k += 8) {
    const __m512d w = _mm512_loadu_pd(qw + k), x = _mm512_loadu_pd(qx + k), y = _mm512_loadu_pd(qy + k),
                  z = _mm512_loadu_pd(qz + k);
    // RotationMatrixOfUnitQuaternion.
    const __m512d tx = _mm512_mul_pd(two, x), ty = _mm512_mul_pd(two, y), tz = _mm512_mul_pd(two, z);
    const __m512d twx = _mm512_mul_pd(tx, w), twy = _mm512_mul_pd(ty, w), twz = _mm512_mul_pd(tz, w);
    const __m512d txx = _mm512_mul_pd(tx, x), txy = _mm512_mul_pd(ty, x), txz = _mm512_mul_pd(tz, x);
    const __m512d tyy = _mm512_mul_pd(ty, y), tyz = _mm512_mul_pd(tz, y), tzz = _mm512_mul_pd(tz, z);
    const __m512d r00 = _mm512_sub_pd(one, _mm512_add_pd(tyy, tzz));
    const __m512d r11 = _mm512_sub_pd(one, _mm512_add_pd(txx, tzz));
    const __m512d r22 = _mm512_sub_pd(one, _mm512_add_pd(txx, tyy));
    const __m512d r10 = _mm512_add_pd(txy, twz);
    const __m512d r20 = _mm512_sub_pd(txz, twy);
    const __m512d r21 = _mm512_add_pd(tyz, twx);
    // RollPitchYaw.
    const __m512d cos_pitch_sq = _mm512_add_pd(_mm512_mul_pd(r21, r21), _mm512_mul_pd(r22, r22));
    if (_mm512_cmp_pd_mask(cos_pitch_sq, gimbal_lock_cos_pitch_sq, _CMP_LT_OQ) != 0) {
      ScalarAngles(quat, k, k + 8, roll_pitch_yaw, dcos);
      continue;
    }
    const __m512d cos_pitch = _mm512_sqrt_pd(_mm512_add_pd(_mm512_mul_pd(r00, r00), _mm512_mul_pd(r10, r10)));
    _mm512_storeu_pd(pitch + k, NapkinAtan2x8(_mm512_xor_pd(r20, sign_bit), cos_pitch));
    _mm512_storeu_pd(roll + k, NapkinAtan2x8(r21, r22));
    _mm512_storeu_pd(yaw + k, NapkinAtan2x8(r10, r00));
    // DirectionCosineAngles.
    _mm512_storeu_pd(dcos_0 + k, NapkinAcosx8(ClampToUnit8(r00)));
    _mm512_storeu_pd(dcos_1 + k, NapkinAcosx8(ClampToUnit8(r11)));
    _mm512_storeu_pd(dcos_2 + k, NapkinAcosx8(ClampToUnit8(r22)));
  }
  return k;
}

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

bool ProcessorHasAvx2() {
  static const bool has_avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return has_avx2;
}

// libmvec's AVX-512 functions need AVX512DQ as well (else they fall back to AVX2 code).
bool ProcessorHasAvx512() {
  static const bool has_avx512 =
      ProcessorHasAvx2() && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq");
  return has_avx512;
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
                       AnglesImplementation implementation) {
  const Index n = quat_fixed_from_body.rows();
  roll_pitch_yaw_rad.resize(n, 3);
  dcos_rad.resize(n, 3);
  Index done = 0;
#if NAPKIN_ANGLES_AVX2
  // Per-sample atan2 and acos were about 30 % of the exact solver's time
  // (perf); libmvec computes four (eight) of each in about the time of one.
  if (implementation == AnglesImplementation::kAvx512 && ProcessorHasAvx512())
    done = Avx512Angles(quat_fixed_from_body, roll_pitch_yaw_rad, dcos_rad);
  else if (implementation != AnglesImplementation::kScalar && ProcessorHasAvx2())
    done = Avx2Angles(quat_fixed_from_body, roll_pitch_yaw_rad, dcos_rad);
#else
  (void)implementation;
#endif
  ScalarAngles(quat_fixed_from_body, done, n, roll_pitch_yaw_rad, dcos_rad);
}

}  // namespace napkin::engine
