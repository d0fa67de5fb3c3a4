// OrientationAngles four samples at a time: compiled with -mavx2 -mfma
// (engine/CMakeLists.txt) where the build links libmvec, empty elsewhere.
#include "engine/rotation_angles_lanes.h"

#if defined(NAPKIN_HAVE_LIBMVEC_AVX2)
std::ptrdiff_t napkin::engine::internal::Avx2AngleRows(const AngleColumns& columns) {
  return VectorAngleRows<__m256d>(columns);
}
#endif
