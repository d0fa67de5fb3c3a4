#pragma once
// UBrIC, the universal brain injury criterion (docs/algorithms.md "Injury
// criteria"): Gabler, L. F., Crandall, J. R., Panzer, M. B., "Development of a
// Metric for Predicting Brain Strain Responses Using Head Kinematics", Annals
// of Biomedical Engineering 46, 2018, pp. 972-985, doi:10.1007/s10439-018-2015-9.
// Header-only: the criterion is this function and its row in
// engine/summary_fields.cpp (docs/developing.md "Adding a criterion").
#include <Eigen/Core>
#include <cmath>
#include <limits>

#include "common/error.h"
#include "engine/finite_samples.h"
#include "engine/kinematics.h"

namespace napkin::engine {

// The paper's critical values for maximum principal strain (MPS), Table 4:
// angular velocity in rad/s and angular acceleration in rad/s², body axes x, y, z.
inline const Eigen::Vector3d kUbricCriticalOmegaRadps{211.0, 171.0, 115.0};
inline const Eigen::Vector3d kUbricCriticalAlphaRadps2{20000.0, 10300.0, 7760.0};
inline constexpr double kUbricExponent = 2.0;  // r, the paper's recommended value

// One axis' term w + (a - w) e^(-a/w) of the normalised peaks w = ω*, a = α*:
// the peak velocity for a short (impulsive) pulse, a/w -> ∞; the peak
// acceleration for a long one, a/w -> 0; w when a = w. A still axis (w = 0)
// contributes 0, its limit for every a.
inline double UbricAxisTerm(double omega_star, double alpha_star) {
  if (omega_star == 0.0) return 0.0;
  return omega_star + (alpha_star - omega_star) * std::exp(-alpha_star / omega_star);
}

// UBrIC = [Σ_i (ω_i* + (α_i* − ω_i*) e^(−α_i*/ω_i*))^r]^(1/r), ω_i* =
// max_t |ω_i| / ω_iC, α_i* = max_t |α_i| / α_iC (body axes; the critical values
// and r above). NaN for kinematics without rotation (an acceleration-only
// array, engine/kinematics.h HasRotation), as BrIC and DAMAGE are; throws
// InputError on a non-finite sample.
inline double Ubric(const Eigen::Ref<const Series3>& omega_body_radps,
                    const Eigen::Ref<const Series3>& alpha_body_radps2) {
  if (omega_body_radps.rows() == 0 || alpha_body_radps2.rows() == 0) return 0.0;
  if (!internal::AllFinite(omega_body_radps) || !internal::AllFinite(alpha_body_radps2))
    throw InputError("UBrIC: the angular velocity or acceleration has a non-finite sample.");
  const Eigen::Vector3d omega_star =
      omega_body_radps.cwiseAbs().colwise().maxCoeff().transpose().cwiseQuotient(kUbricCriticalOmegaRadps);
  const Eigen::Vector3d alpha_star =
      alpha_body_radps2.cwiseAbs().colwise().maxCoeff().transpose().cwiseQuotient(kUbricCriticalAlphaRadps2);
  double sum = 0.0;
  for (int axis = 0; axis < 3; ++axis)
    sum += std::pow(UbricAxisTerm(omega_star[axis], alpha_star[axis]), kUbricExponent);
  return std::pow(sum, 1.0 / kUbricExponent);
}

// UBrIC of solved kinematics (SummaryField::compute): NaN without rotation.
inline double UbricOf(const Kinematics& kinematics) {
  if (!HasRotation(kinematics)) return std::numeric_limits<double>::quiet_NaN();
  return Ubric(kinematics.omega_body, kinematics.alpha_body);
}

}  // namespace napkin::engine
