#include "tests/support/reference_arrays.h"

#include <array>

#include "engine/units.h"

namespace napkin::test_support {
namespace {

using engine::ArrayGeometry;
using engine::Sensor;
using engine::SensorKind;

// Sense axes of the nine slots, Table 2-1 order.
// One row per arm, as in the report's Table 2-1.
// clang-format off
constexpr std::array<std::array<double, 3>, 9> kNapAxes = {{
    {1, 0, 0}, {0, 1, 0}, {0, 0, 1},  // cg_x, cg_y, cg_z
    {0, 0, 1}, {1, 0, 0},             // yarm_z, yarm_x
    {0, 0, 1}, {0, 1, 0},             // xarm_z, xarm_y
    {1, 0, 0}, {0, 1, 0},             // zarm_x, zarm_y
}};
// clang-format on

ArrayGeometry Nap(const char* name, const std::array<std::array<double, 3>, 9>& positions_in) {
  ArrayGeometry array;
  array.name = name;
  for (int i = 0; i < 9; ++i) {
    Sensor sensor;
    sensor.slot = engine::kNapSlots[i];
    sensor.kind = SensorKind::kLinear;
    sensor.position_body_m =
        Eigen::Vector3d(positions_in[i][0], positions_in[i][1], positions_in[i][2]) * engine::kMetresPerInch;
    sensor.axis_body = Eigen::Vector3d(kNapAxes[i][0], kNapAxes[i][1], kNapAxes[i][2]);
    sensor.unit = "g";
    sensor.si_per_unit = engine::kStandardGravity;
    array.sensors.push_back(sensor);
  }
  return array;
}

void AddRateSensors(ArrayGeometry& array) {
  const char* slots[3] = {"ars_x", "ars_y", "ars_z"};
  for (int i = 0; i < 3; ++i) {
    Sensor sensor;
    sensor.slot = slots[i];
    sensor.kind = SensorKind::kAngularRate;
    sensor.position_body_m.setZero();
    sensor.axis_body = Eigen::Vector3d::Unit(i);
    sensor.unit = "rad/s";
    sensor.si_per_unit = 1.0;
    array.sensors.push_back(sensor);
  }
}

}  // namespace

ArrayGeometry Ideal3222() {
  return Nap("ideal-3222", {{{0, 0, 0},
                             {0, 0, 0},
                             {0, 0, 0},
                             {0, 1.9, 0},
                             {0, 1.9, 0},
                             {2.2, 0, 0},
                             {2.2, 0, 0},
                             {0, 0, 3.2},
                             {0, 0, 3.2}}});
}

ArrayGeometry VolpeTable42() {
  return Nap("volpe-table4-2", {{{0.203, 0, 0},
                                 {0, 0.203, 0},
                                 {0, 0, 0.203},
                                 {0, 2.103, 0},
                                 {0, 1.900, 0.203},
                                 {2.403, 0, 0},
                                 {2.200, 0, 0.203},
                                 {0.203, 0, 3.200},
                                 {0, 0.203, 3.200}}});
}

ArrayGeometry Denton3222() {
  return Nap("denton-3222", {{{0.203, 0, 0},
                              {0, 0.203, 0},
                              {0, 0, 0.203},
                              {0, 1.900, 0.203},
                              {0.203, 1.900, 0},
                              {2.200, 0, 0.203},
                              {2.200, 0.203, 0},
                              {0.203, 0, 3.200},
                              {0, 0.203, 3.200}}});
}

ArrayGeometry SixAOmegaCg() {
  ArrayGeometry array = Ideal3222();
  array.name = "6aw-cg";
  array.sensors.resize(3);  // cg_x, cg_y, cg_z at the CG
  AddRateSensors(array);
  return array;
}

ArrayGeometry ThreeACg() {
  ArrayGeometry array = Ideal3222();
  array.name = "3a-cg";
  array.sensors.resize(3);  // cg_x, cg_y, cg_z at the CG
  return array;
}

ArrayGeometry NapArs12() {
  ArrayGeometry array = Denton3222();
  array.name = "nap-ars-12";
  AddRateSensors(array);
  return array;
}

ArrayGeometry OneLinearOneRate() {
  ArrayGeometry array;
  array.name = "test";
  Sensor linear;
  linear.slot = "cg_x";
  linear.kind = SensorKind::kLinear;
  Sensor rate;
  rate.slot = "ars_x";
  rate.kind = SensorKind::kAngularRate;
  rate.unit = "rad/s";
  rate.si_per_unit = 1.0;
  array.sensors = {linear, rate};
  return array;
}

}  // namespace napkin::test_support
