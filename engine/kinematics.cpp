#include "engine/kinematics.h"

namespace napkin::engine {

void Kinematics::Resize(Eigen::Index n) {
  time_s.resize(n);
  for (Series3* series : {&omega_body, &alpha_body, &omega_fixed, &alpha_fixed, &acc_body, &acc_fixed,
                          &vel_fixed, &pos_fixed, &roll_pitch_yaw_rad, &dcos_rad})
    series->resize(n, 3);
  quat_fixed_from_body.resize(n, 4);
  residual.setZero(n);
}

void Kinematics::ResizeWithoutRotation(Eigen::Index n) {
  time_s.resize(n);
  acc_body.resize(n, 3);
  for (Series3* series : {&omega_body, &alpha_body, &omega_fixed, &alpha_fixed, &acc_fixed, &vel_fixed,
                          &pos_fixed, &roll_pitch_yaw_rad, &dcos_rad})
    series->resize(0, 3);
  quat_fixed_from_body.resize(0, 4);
  residual.resize(0);
}

void Kinematics::ResizeForSummary(Eigen::Index n) {
  time_s.resize(n);
  for (Series3* series : {&omega_body, &alpha_body, &acc_body, &acc_fixed, &vel_fixed, &pos_fixed})
    series->resize(n, 3);
  for (Series3* series : {&omega_fixed, &alpha_fixed, &roll_pitch_yaw_rad, &dcos_rad}) series->resize(0, 3);
  quat_fixed_from_body.resize(n, 4);
  residual.setZero(n);
}

bool HasRotation(const Kinematics& kinematics) {
  return kinematics.size() == 0 || (kinematics.quat_fixed_from_body.rows() == kinematics.size() &&
                                    kinematics.quat_fixed_from_body.row(0).allFinite());
}

}  // namespace napkin::engine
