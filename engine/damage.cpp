// DAMAGE (engine/damage.h; docs/algorithms.md "Injury criteria").
#include "engine/damage.h"

#include <cmath>
#include <unsupported/Eigen/MatrixFunctions>

#include "common/error.h"
#include "engine/cancellation.h"
#include "engine/criterion_checks.h"
#include "engine/finite_samples.h"

namespace napkin::engine {

using internal::CheckInterval;

Eigen::Matrix3d DamageModel::Stiffness() const {
  Eigen::Matrix3d k;
  k << kxx + kxy + kxz, -kxy, -kxz,  //
      -kxy, kxy + kyy + kyz, -kyz,   //
      -kxz, -kyz, kxz + kyz + kzz;
  return k;
}

namespace {

// DamageDisplacement into `displacement` (its memory reused when as long).
void DamageDisplacementIn(const Eigen::Ref<const Series3>& alpha_body_radps2, double dt_s,
                          const DamageModel& model, const std::atomic<bool>* cancel, Series3& displacement) {
  CheckInterval(dt_s, "DAMAGE");
  if (!internal::AllFinite(alpha_body_radps2))
    throw InputError("DAMAGE: the angular acceleration has a non-finite sample.");
  if (!(std::isfinite(model.mass_kg) && model.mass_kg > 0.0))
    throw InputError("DAMAGE: the mass is not positive.");
  const Eigen::Index n = alpha_body_radps2.rows();
  displacement.setZero(n, 3);
  if (n < 2) return;

  // x = [d; d'],  x' = A x + B alpha,  A = [[0, I], [-K/m, -C/m]],  B = [0; I].
  const Eigen::Matrix3d stiffness_per_mass = model.Stiffness() / model.mass_kg;
  Eigen::Matrix<double, 6, 6> system = Eigen::Matrix<double, 6, 6>::Zero();
  system.topRightCorner<3, 3>().setIdentity();
  system.bottomLeftCorner<3, 3>() = -stiffness_per_mass;
  system.bottomRightCorner<3, 3>() = -model.a1_s * stiffness_per_mass;
  // With alpha(t_k + s dt) = alpha_k + s (alpha_{k+1} - alpha_k), the
  // augmented state z = [x; alpha; delta_alpha] obeys dz/ds = Z z with
  // Z = [[A dt, B dt, 0], [0, 0, I], [0, 0, 0]]; exp(Z) = [[Phi, G0, G1], ...].
  Eigen::Matrix<double, 12, 12> augmented = Eigen::Matrix<double, 12, 12>::Zero();
  augmented.topLeftCorner<6, 6>() = system * dt_s;
  augmented.block<3, 3>(3, 6) = Eigen::Matrix3d::Identity() * dt_s;
  augmented.block<3, 3>(6, 9).setIdentity();
  const Eigen::Matrix<double, 12, 12> transition = augmented.exp();
  const Eigen::Matrix<double, 6, 6> phi = transition.topLeftCorner<6, 6>();
  const Eigen::Matrix<double, 6, 3> gamma_value = transition.block<6, 3>(0, 6);
  const Eigen::Matrix<double, 6, 3> gamma_slope = transition.block<6, 3>(0, 9);

  Eigen::Matrix<double, 6, 1> state = Eigen::Matrix<double, 6, 1>::Zero();
  for (Eigen::Index k = 0; k + 1 < n; ++k) {
    ThrowIfCancelled(cancel, k);
    const Eigen::Vector3d alpha_k = alpha_body_radps2.row(k).transpose();
    const Eigen::Vector3d alpha_next = alpha_body_radps2.row(k + 1).transpose();
    state = phi * state + gamma_value * alpha_k + gamma_slope * (alpha_next - alpha_k);
    displacement.row(k + 1) = state.head<3>().transpose();
  }
}

}  // namespace

double Damage(const Eigen::Ref<const Series3>& alpha_body_radps2, double dt_s, const DamageModel& model,
              const std::atomic<bool>* cancel, Series3& displacement) {
  DamageDisplacementIn(alpha_body_radps2, dt_s, model, cancel, displacement);
  if (displacement.rows() == 0) return 0.0;
  return model.beta_per_m * displacement.rowwise().norm().maxCoeff();
}

Series3 DamageDisplacement(const Eigen::Ref<const Series3>& alpha_body_radps2, double dt_s,
                           const DamageModel& model, const std::atomic<bool>* cancel) {
  Series3 displacement;
  DamageDisplacementIn(alpha_body_radps2, dt_s, model, cancel, displacement);
  return displacement;
}

double Damage(const Eigen::Ref<const Series3>& alpha_body_radps2, double dt_s, const DamageModel& model,
              const std::atomic<bool>* cancel) {
  Series3 displacement;
  return Damage(alpha_body_radps2, dt_s, model, cancel, displacement);
}

}  // namespace napkin::engine
