#pragma once
// The vectorized angle loop of OrientationAngles (engine/rotation_angles.h),
// written once for any vector width; internal to engine/rotation_angles*.cpp.
// rotation_angles_avx2.cpp and rotation_angles_avx512.cpp include it and are
// compiled for their instruction set (engine/CMakeLists.txt), each
// instantiating the loop with its own width. So that no code compiled for
// AVX2 or AVX-512 can ever run on a processor without it, those two files
// define nothing inline with external linkage (the linker could keep their
// copy for every caller): the loop and its helpers have internal linkage and
// work on raw columns, and the scalar rows are a call into rotation_angles.cpp.
#include <cstddef>

namespace napkin::engine::internal {

// OrientationAngles' input and output series, column by column (Eigen's
// series are column-major).
struct AngleColumns {
  std::ptrdiff_t rows = 0;
  const double *qw = nullptr, *qx = nullptr, *qy = nullptr, *qz = nullptr;
  double *roll = nullptr, *pitch = nullptr, *yaw = nullptr;
  double* dcos[3] = {nullptr, nullptr, nullptr};
};

// Rows [begin, end) with engine/rotation.h's scalar functions (rotation_angles.cpp).
void ScalarAngleRows(const AngleColumns& columns, std::ptrdiff_t begin, std::ptrdiff_t end);

// The rows done from row 0, four (eight) at a time: a multiple of 4 (8).
// Call only on a processor with AVX2 and FMA (AVX-512 F and DQ as well).
std::ptrdiff_t Avx2AngleRows(const AngleColumns& columns);
std::ptrdiff_t Avx512AngleRows(const AngleColumns& columns);

}  // namespace napkin::engine::internal

#if defined(__AVX2__)  // rotation_angles_avx2.cpp and rotation_angles_avx512.cpp
#include <immintrin.h>

#include <cstring>

#define NAPKIN_TARGET_AVX2 __attribute__((target("avx2,fma")))
#define NAPKIN_TARGET_AVX512 __attribute__((target("avx512f,avx512dq,avx2,fma")))

// glibc's libmvec (vector function ABI, "d" = AVX2, 4 lanes, "e" = AVX-512,
// 8 lanes): atan2(y, x) and acos(x) of each lane, to within a few ulp of libm's.
NAPKIN_TARGET_AVX2 __m256d NapkinAtan2x4(__m256d y, __m256d x) __asm__("_ZGVdN4vv_atan2");
NAPKIN_TARGET_AVX2 __m256d NapkinAcosx4(__m256d x) __asm__("_ZGVdN4v_acos");
NAPKIN_TARGET_AVX512 __m512d NapkinAtan2x8(__m512d y, __m512d x) __asm__("_ZGVeN8vv_atan2");
NAPKIN_TARGET_AVX512 __m512d NapkinAcosx8(__m512d x) __asm__("_ZGVeN8v_acos");

// GCC 12's AVX-512 intrinsics read an undefined vector (_mm512_undefined_pd)
// that -Wmaybe-uninitialized flags (a false positive fixed in GCC 13).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

namespace napkin::engine::internal {
namespace {

// Doubles (__m256d: 4 lanes, __m512d: 8) is one register of doubles.
// Arithmetic and comparisons are the compiler's vector operators (lane by
// lane, IEEE as the scalar code; the files are compiled without
// floating-point contraction, so no FMA); only sqrt, the any-lane test,
// atan2 and acos name the instruction set, in these overloads. AnyBelow:
// whether a lane is below `limit` (false for NaN, as the scalar `<`).
inline __m256d Sqrt(__m256d v) { return _mm256_sqrt_pd(v); }
inline bool AnyBelow(__m256d v, double limit) {
  return _mm256_movemask_pd(_mm256_cmp_pd(v, _mm256_set1_pd(limit), _CMP_LT_OQ)) != 0;
}
inline __m256d Atan2(__m256d y, __m256d x) { return NapkinAtan2x4(y, x); }
inline __m256d Acos(__m256d x) { return NapkinAcosx4(x); }
#if defined(__AVX512F__)
inline __m512d Sqrt(__m512d v) { return _mm512_sqrt_pd(v); }
inline bool AnyBelow(__m512d v, double limit) {
  return _mm512_cmp_pd_mask(v, _mm512_set1_pd(limit), _CMP_LT_OQ) != 0;
}
inline __m512d Atan2(__m512d y, __m512d x) { return NapkinAtan2x8(y, x); }
inline __m512d Acos(__m512d x) { return NapkinAcosx8(x); }
#endif

template <typename Doubles>
Doubles Load(const double* from) {
  Doubles lanes;
  std::memcpy(&lanes, from, sizeof lanes);
  return lanes;
}

template <typename Doubles>
void Store(double* to, Doubles lanes) {
  std::memcpy(to, &lanes, sizeof lanes);
}

// std::clamp(v, -1.0, 1.0) lane by lane, NaN kept (it fails both comparisons).
template <typename Doubles>
Doubles ClampToUnit(Doubles v) {
  const Doubles minus_one = Doubles{} - 1.0, one = Doubles{} + 1.0;
  v = v < minus_one ? minus_one : v;
  return v > one ? one : v;
}

// The scalar code of engine/rotation_angles.h and engine/rotation.h kLanes
// samples at a time: the same rotation-matrix entries, operation for
// operation, and the same sqrt; only atan2 and acos are libmvec's. A block
// with a sample at gimbal lock (RollPitchYaw's cos(pitch)^2 < 1e-24 branch)
// is done by the scalar code. NaN propagates as in the scalar code: a NaN
// quaternion fails the gimbal-lock test, atan2 and acos of NaN are NaN, and
// the clamp keeps NaN. Returns the number of rows done, a multiple of the
// lanes of Doubles.
template <typename Doubles>
std::ptrdiff_t VectorAngleRows(const AngleColumns& columns) {
  constexpr std::ptrdiff_t kLanes = sizeof(Doubles) / sizeof(double);
  std::ptrdiff_t k = 0;
  for (; k + kLanes <= columns.rows; k += kLanes) {
    const Doubles w = Load<Doubles>(columns.qw + k), x = Load<Doubles>(columns.qx + k),
                  y = Load<Doubles>(columns.qy + k), z = Load<Doubles>(columns.qz + k);
    // RotationMatrixOfUnitQuaternion.
    const Doubles tx = 2.0 * x, ty = 2.0 * y, tz = 2.0 * z;
    const Doubles twx = tx * w, twy = ty * w, twz = tz * w;
    const Doubles txx = tx * x, txy = ty * x, txz = tz * x;
    const Doubles tyy = ty * y, tyz = tz * y, tzz = tz * z;
    const Doubles r00 = 1.0 - (tyy + tzz), r11 = 1.0 - (txx + tzz), r22 = 1.0 - (txx + tyy);
    const Doubles r10 = txy + twz, r20 = txz - twy, r21 = tyz + twx;
    // RollPitchYaw.
    if (AnyBelow(r21 * r21 + r22 * r22, 1e-24)) {
      ScalarAngleRows(columns, k, k + kLanes);
      continue;
    }
    Store(columns.pitch + k, Atan2(-r20, Sqrt(r00 * r00 + r10 * r10)));
    Store(columns.roll + k, Atan2(r21, r22));
    Store(columns.yaw + k, Atan2(r10, r00));
    // DirectionCosineAngles.
    Store(columns.dcos[0] + k, Acos(ClampToUnit(r00)));
    Store(columns.dcos[1] + k, Acos(ClampToUnit(r11)));
    Store(columns.dcos[2] + k, Acos(ClampToUnit(r22)));
  }
  return k;
}

}  // namespace
}  // namespace napkin::engine::internal

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
#endif  // __AVX2__
