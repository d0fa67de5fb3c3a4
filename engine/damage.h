#pragma once
// DAMAGE, the brain-strain criterion of Gabler et al. 2019 (docs/algorithms.md
// "Injury criteria").
#include <Eigen/Core>
#include <atomic>

#include "engine/kinematics.h"

namespace napkin::engine {

// ---------------------------------------------------------------------------
// DAMAGE (Gabler et al. 2019): the coupled mass-spring-damper
//   M d'' + C d' + K d = M alpha(t),   d(t0) = d'(t0) = 0,
// driven by the body angular acceleration (rad/s^2), with
//   M = m I, K = [[kxx+kxy+kxz, -kxy, -kxz], [-kxy, kxy+kyy+kyz, -kyz],
//                 [-kxz, -kyz, kxz+kyz+kzz]],  C = a1 K,
//   DAMAGE = beta * max_k ||d(t_k)||.
// Integrated exactly for alpha linear between samples (state-space
// discretisation by one matrix exponential of the system augmented with the
// input and its slope), so the only error is the linear interpolation of alpha.
struct DamageModel {
  double mass_kg = 1.0;        // m, each axis
  double kxx = 32142.0;        // N/m
  double kyy = 23493.0;        // N/m
  double kzz = 16935.0;        // N/m
  double kxy = 0.0;            // N/m
  double kyz = 0.0;            // N/m
  double kxz = 1636.3;         // N/m
  double a1_s = 5.9148e-3;     // stiffness-proportional damping, C = a1 K (s)
  double beta_per_m = 2.9903;  // DAMAGE = beta * max ||d||

  Eigen::Matrix3d Stiffness() const;
};

// Displacement d(t_k) (m) of the DAMAGE model at every sample. Throws
// Cancelled once `cancel` is set (engine/cancellation.h).
Series3 DamageDisplacement(const Eigen::Ref<const Series3>& alpha_body_radps2, double dt_s,
                           const DamageModel& model = {}, const std::atomic<bool>* cancel = nullptr);
double Damage(const Eigen::Ref<const Series3>& alpha_body_radps2, double dt_s, const DamageModel& model = {},
              const std::atomic<bool>* cancel = nullptr);
// Damage with the model's response in `displacement` (its memory reused when as long).
double Damage(const Eigen::Ref<const Series3>& alpha_body_radps2, double dt_s, const DamageModel& model,
              const std::atomic<bool>* cancel, Series3& displacement);

}  // namespace napkin::engine
