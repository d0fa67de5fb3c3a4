#include "engine/integration.h"

#include "engine/rotation.h"

namespace napkin::engine {

Eigen::MatrixXd DifferentiateSecondOrder(const Eigen::MatrixXd& f, double dt) {
  const Eigen::Index n = f.rows();
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(n, f.cols());
  if (n < 2) return d;
  if (n == 2) {
    d.row(0) = (f.row(1) - f.row(0)) / dt;
    d.row(1) = d.row(0);
    return d;
  }
  const double inv_2dt = 0.5 / dt;
  d.middleRows(1, n - 2) = (f.bottomRows(n - 2) - f.topRows(n - 2)) * inv_2dt;
  d.row(0) = (-3.0 * f.row(0) + 4.0 * f.row(1) - f.row(2)) * inv_2dt;
  d.row(n - 1) = (3.0 * f.row(n - 1) - 4.0 * f.row(n - 2) + f.row(n - 3)) * inv_2dt;
  return d;
}

Eigen::MatrixXd DifferentiateFourthOrder(const Eigen::MatrixXd& f, double dt) {
  const Eigen::Index n = f.rows();
  if (n < 5) return DifferentiateSecondOrder(f, dt);
  Eigen::MatrixXd d(n, f.cols());
  const double inv_12dt = 1.0 / (12.0 * dt);
  d.middleRows(2, n - 4) = (-f.bottomRows(n - 4) + 8.0 * f.middleRows(3, n - 4) -
                            8.0 * f.middleRows(1, n - 4) + f.topRows(n - 4)) *
                           inv_12dt;
  d.row(0) =
      (-25.0 * f.row(0) + 48.0 * f.row(1) - 36.0 * f.row(2) + 16.0 * f.row(3) - 3.0 * f.row(4)) * inv_12dt;
  d.row(1) = (-3.0 * f.row(0) - 10.0 * f.row(1) + 18.0 * f.row(2) - 6.0 * f.row(3) + f.row(4)) * inv_12dt;
  d.row(n - 1) = (25.0 * f.row(n - 1) - 48.0 * f.row(n - 2) + 36.0 * f.row(n - 3) - 16.0 * f.row(n - 4) +
                  3.0 * f.row(n - 5)) *
                 inv_12dt;
  d.row(n - 2) =
      (3.0 * f.row(n - 1) + 10.0 * f.row(n - 2) - 18.0 * f.row(n - 3) + 6.0 * f.row(n - 4) - f.row(n - 5)) *
      inv_12dt;
  return d;
}

void IntegrateHermite(double dt, const Series3& f, const Series3& f_dot, const Eigen::Vector3d& y0,
                      Series3& y) {
  const Eigen::Index n = f.rows();
  y.resize(n, 3);
  if (n == 0) return;
  const double half_dt = 0.5 * dt, dt2_12 = dt * dt / 12.0;
  y.row(0) = y0.transpose();
  for (Eigen::Index k = 1; k < n; ++k)
    y.row(k) =
        y.row(k - 1) + half_dt * (f.row(k - 1) + f.row(k)) + dt2_12 * (f_dot.row(k - 1) - f_dot.row(k));
}

void IntegrateOrientation(double dt, const Series3& omega_body, const Series3& alpha_body,
                          const Eigen::Quaterniond& fixed_from_body_0, Series4& quat_wxyz) {
  const Eigen::Index n = omega_body.rows();
  quat_wxyz.resize(n, 4);
  if (n == 0) return;
  const double half_dt = 0.5 * dt, dt2_12 = dt * dt / 12.0;
  Eigen::Quaterniond q = fixed_from_body_0.normalized();
  quat_wxyz.row(0) << q.w(), q.x(), q.y(), q.z();
  for (Eigen::Index k = 1; k < n; ++k) {
    const Eigen::Vector3d w0 = omega_body.row(k - 1).transpose(), w1 = omega_body.row(k).transpose();
    const Eigen::Vector3d a0 = alpha_body.row(k - 1).transpose(), a1 = alpha_body.row(k).transpose();
    const Eigen::Vector3d step_rotation = half_dt * (w0 + w1) + dt2_12 * (a0 - a1) + dt2_12 * w0.cross(w1);
    // Body-frame increment multiplies on the right: dR/dt = R [omega_body]x.
    q = (q * QuaternionExp(step_rotation)).normalized();
    quat_wxyz.row(k) << q.w(), q.x(), q.y(), q.z();
  }
}

}  // namespace napkin::engine
