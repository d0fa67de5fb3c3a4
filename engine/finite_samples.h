#pragma once
// Whether every sample of a series is finite, in a loop the compiler
// vectorizes (engine-internal). Eigen's allFinite() compares coefficient
// after coefficient in a scalar loop that stops at the first failure; the
// pipeline asks it of a dozen series of every test, all finite.
#include <Eigen/Core>

namespace napkin::engine::internal {

// Whether samples[0 .. count) are all finite (no infinity, no NaN).
bool AllFinite(const double* samples, Eigen::Index count);

// Whether every coefficient of a column-major matrix or vector whose columns
// are contiguous (a series of engine/kinematics.h, a column of one) is finite:
// the same answer as Eigen's allFinite().
template <typename Derived>
bool AllFinite(const Eigen::DenseBase<Derived>& series) {
  static_assert(!Derived::IsRowMajor || Derived::ColsAtCompileTime == 1);
  static_assert(Derived::InnerStrideAtCompileTime == 1);
  const Derived& matrix = series.derived();
  for (Eigen::Index c = 0; c < matrix.cols(); ++c)
    if (!AllFinite(matrix.col(c).data(), matrix.rows())) return false;
  return true;
}

}  // namespace napkin::engine::internal
