#include "engine/array_geometry.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>
#include <set>
#include <sstream>

#include "common/error.h"
#include "engine/array_analysis.h"

namespace napkin::engine {

std::optional<std::size_t> ArrayGeometry::FindSlot(std::string_view slot) const {
  for (std::size_t i = 0; i < sensors.size(); ++i)
    if (sensors[i].slot == slot) return i;
  return std::nullopt;
}

std::vector<std::size_t> ArrayGeometry::LinearIndices() const {
  std::vector<std::size_t> indices;
  for (std::size_t i = 0; i < sensors.size(); ++i)
    if (sensors[i].kind == SensorKind::kLinear) indices.push_back(i);
  return indices;
}

std::vector<std::size_t> ArrayGeometry::CgLinearIndices() const {
  std::vector<std::size_t> indices;
  for (std::size_t i = 0; i < sensors.size(); ++i)
    if (sensors[i].kind == SensorKind::kLinear && sensors[i].position_body_m.norm() <= kAtCgToleranceM)
      indices.push_back(i);
  return indices;
}

bool DeterminesRotation(const ArrayGeometry& validated_array) {
  return LinearRigidBodyRank(validated_array, validated_array.LinearIndices()) == 6 ||
         NumericalRank(SenseAxisRows(validated_array, validated_array.RateIndices())) == 3;
}

std::vector<std::size_t> ArrayGeometry::RateIndices() const {
  std::vector<std::size_t> indices;
  for (std::size_t i = 0; i < sensors.size(); ++i)
    if (sensors[i].kind == SensorKind::kAngularRate) indices.push_back(i);
  return indices;
}

Eigen::MatrixXd LinearRigidBodyRows(const ArrayGeometry& array, const std::vector<std::size_t>& linear) {
  Eigen::MatrixXd rows(static_cast<Eigen::Index>(linear.size()), 6);
  for (std::size_t i = 0; i < linear.size(); ++i) {
    const Sensor& sensor = array.sensors[linear[i]];
    const auto row = static_cast<Eigen::Index>(i);
    rows.block<1, 3>(row, 0) = sensor.axis_body.transpose();
    rows.block<1, 3>(row, 3) = sensor.position_body_m.cross(sensor.axis_body).transpose();
  }
  return rows;
}

Eigen::MatrixXd SenseAxisRows(const ArrayGeometry& array, const std::vector<std::size_t>& indices) {
  Eigen::MatrixXd rows(static_cast<Eigen::Index>(indices.size()), 3);
  for (std::size_t i = 0; i < indices.size(); ++i)
    rows.row(static_cast<Eigen::Index>(i)) = array.sensors[indices[i]].axis_body.transpose();
  return rows;
}

double RmsLeverArm(const ArrayGeometry& array, const std::vector<std::size_t>& indices) {
  if (indices.empty()) return 0.0;
  double sum_sq = 0.0;
  for (std::size_t index : indices) sum_sq += array.sensors[index].position_body_m.squaredNorm();
  return std::sqrt(sum_sq / static_cast<double>(indices.size()));
}

int NumericalRank(const Eigen::MatrixXd& m) {
  if (m.size() == 0) return 0;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(m);
  const Eigen::VectorXd& sv = svd.singularValues();
  if (sv.size() == 0 || !(sv(0) > 0.0)) return 0;
  int rank = 0;
  for (Eigen::Index i = 0; i < sv.size(); ++i)
    if (sv(i) > kRankRelativeTolerance * sv(0)) ++rank;
  return rank;
}

int LinearRigidBodyRank(const ArrayGeometry& array, const std::vector<std::size_t>& linear) {
  Eigen::MatrixXd rows = LinearRigidBodyRows(array, linear);
  const double lever_m = RmsLeverArm(array, linear);
  if (lever_m > 0.0) rows.rightCols(3) /= lever_m;
  return NumericalRank(rows);
}

Eigen::MatrixXd PseudoInverse(const Eigen::MatrixXd& m) {
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(m, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& sv = svd.singularValues();
  Eigen::VectorXd inverse_sv = Eigen::VectorXd::Zero(sv.size());
  for (Eigen::Index i = 0; i < sv.size(); ++i)
    if (sv(i) > kRankRelativeTolerance * sv(0)) inverse_sv(i) = 1.0 / sv(i);
  return svd.matrixV() * inverse_sv.asDiagonal() * svd.matrixU().transpose();
}

void ValidateArray(ArrayGeometry& array) {
  const std::string label = "array '" + (array.name.empty() ? std::string("(unnamed)") : array.name) + "'";
  if (array.sensors.empty()) throw InvalidArrayError(label + " has no sensors.");

  std::set<std::string> seen;
  for (std::size_t i = 0; i < array.sensors.size(); ++i) {
    Sensor& sensor = array.sensors[i];
    if (sensor.slot.empty())
      throw InvalidArrayError(label + ": sensor " + std::to_string(i + 1) + " has an empty slot name.");
    const std::string slot = label + ": slot '" + sensor.slot + "'";
    if (!seen.insert(sensor.slot).second) throw InvalidArrayError(slot + " appears more than once.");
    if (!sensor.position_body_m.allFinite()) throw InvalidArrayError(slot + " has a non-finite position.");
    const double axis_norm = sensor.axis_body.norm();
    if (!std::isfinite(axis_norm) || axis_norm < 1e-12)
      throw InvalidArrayError(slot + " has a zero or non-finite sense axis.");
    if (!std::isfinite(sensor.si_per_unit) || sensor.si_per_unit <= 0.0)
      throw InvalidArrayError(slot + " has unknown unit '" + sensor.unit +
                              "' (no positive, finite factor to SI).");
    sensor.axis_body /= axis_norm;
  }

  // Solvability (docs/algorithms.md "Solvers"): either the linear sensors alone
  // determine (a, alpha), or angular-rate sensors give omega on three
  // independent axes and the linear sense axes span R^3 (6a-omega), or
  // neither determines rotation and linear sensors at the CG span R^3
  // (acceleration only, docs/algorithms.md "Acceleration-only arrays").
  const std::vector<std::size_t> linear = array.LinearIndices();
  const std::vector<std::size_t> rates = array.RateIndices();
  const int linear_rank = LinearRigidBodyRank(array, linear);
  if (linear_rank == 6) return;
  const int rate_rank = NumericalRank(SenseAxisRows(array, rates));
  const int linear_axis_rank = NumericalRank(SenseAxisRows(array, linear));
  if (rate_rank == 3 && linear_axis_rank == 3) return;
  const int cg_axis_rank = NumericalRank(SenseAxisRows(array, array.CgLinearIndices()));
  if (rate_rank < 3 && cg_axis_rank == 3) return;

  std::ostringstream message;
  if (rate_rank == 3) {
    message << label << ": the linear sense axes span only " << linear_axis_rank
            << " of 3 directions, so the CG acceleration is undetermined; add a linear sensor along the "
               "missing axis.";
  } else {
    message << label << ": the linear sensors do not determine the six rigid-body accelerations (rank "
            << linear_rank << " of 6)";
    if (!rates.empty()) message << " and the angular-rate sensors span only " << rate_rank << " of 3 axes";
    message << ", and the linear sensors at the CG span only " << cg_axis_rank
            << " of 3 directions, so neither rotation nor the CG acceleration is determined; add sensors off "
               "the CG, angular-rate sensors, or a triaxial accelerometer at the CG.";
  }
  throw InvalidArrayError(message.str());
}

}  // namespace napkin::engine
