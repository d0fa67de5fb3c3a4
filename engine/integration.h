#pragma once
// Time integration and differentiation of uniformly sampled series, and the
// orientation integrator on SO(3) (docs/algorithms.md "Orientation").
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "engine/kinematics.h"

namespace napkin::engine {

// Derivative of every column of `f` (rows = samples, spacing dt):
// second-order central differences inside, second-order one-sided at the
// ends (first-order when there are only two samples).
Eigen::MatrixXd DifferentiateSecondOrder(const Eigen::MatrixXd& f, double dt);

// Derivative of every column of `f`, fourth order: the five-point central
// stencil (-f[k+2] + 8 f[k+1] - 8 f[k-1] + f[k-2]) / (12 dt) inside and
// fourth-order one-sided stencils on the first and last two samples.
// Falls back to DifferentiateSecondOrder below five samples.
Eigen::MatrixXd DifferentiateFourthOrder(const Eigen::MatrixXd& f, double dt);

// Corrected trapezoidal (Hermite, Euler-Maclaurin) rule:
//   y[k] = y[k-1] + dt/2 (f[k-1] + f[k]) + dt^2/12 (f'[k-1] - f'[k]),
// exact for cubics. The correction telescopes, so a poor derivative at one
// sample (a kink in f) only disturbs that sample, never the running sum.
void IntegrateHermite(double dt, const Series3& f, const Series3& f_dot, const Eigen::Vector3d& y0,
                      Series3& y);

// Body-to-fixed orientation from body angular velocity and acceleration:
//   q[k] = q[k-1] * Exp(theta_k),
//   theta_k = dt/2 (w[k-1] + w[k]) + dt^2/12 (alpha[k-1] - alpha[k])
//             + dt^2/12 (w[k-1] x w[k])    (coning correction, Bortz equation
// with omega linear over the step), renormalised every step. q[0] =
// fixed_from_body_0. Output rows are (w, x, y, z).
void IntegrateOrientation(double dt, const Series3& omega_body, const Series3& alpha_body,
                          const Eigen::Quaterniond& fixed_from_body_0, Series4& quat_wxyz);

// Quaternion of row k of a Series4 (w, x, y, z).
inline Eigen::Quaterniond QuatAt(const Series4& quat_wxyz, Eigen::Index k) {
  return Eigen::Quaterniond(quat_wxyz(k, 0), quat_wxyz(k, 1), quat_wxyz(k, 2), quat_wxyz(k, 3));
}

}  // namespace napkin::engine
