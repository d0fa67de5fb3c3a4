#pragma once
// Linear-algebra facts about an array geometry that both validation and the
// exact solver need: the rigid-body measurement rows and their ranks.
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "engine/array_geometry.h"

namespace napkin::engine {

// Relative singular-value tolerance for the rank decisions below.
inline constexpr double kRankRelativeTolerance = 1e-8;

// Rows [n^T, (r x n)^T] of the linear sensors `linear` (docs/algorithms.md
// "Rigid-body measurement model": n.(a + alpha x r) = n.a + (r x n).alpha).
Eigen::MatrixXd LinearRigidBodyRows(const ArrayGeometry& array, const std::vector<std::size_t>& linear);

// Rows n^T of the sensors `indices` (sense axes only).
Eigen::MatrixXd SenseAxisRows(const ArrayGeometry& array, const std::vector<std::size_t>& indices);

// Root-mean-square distance of the sensors `indices` from the CG (m).
double RmsLeverArm(const ArrayGeometry& array, const std::vector<std::size_t>& indices);

// Numerical rank of `m` (singular values above kRankRelativeTolerance times
// the largest one).
int NumericalRank(const Eigen::MatrixXd& m);

// Rank of the linear sensors' rigid-body rows, with the alpha columns scaled
// by the RMS lever arm so that both halves are dimensionless (m/s^2 per
// m/s^2) and the relative tolerance means the same for any array size.
int LinearRigidBodyRank(const ArrayGeometry& array, const std::vector<std::size_t>& linear);

// Moore-Penrose pseudo-inverse (least-squares solution operator) via SVD.
Eigen::MatrixXd PseudoInverse(const Eigen::MatrixXd& m);

}  // namespace napkin::engine
