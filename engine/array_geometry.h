#pragma once
// Head accelerometer array geometry: which sensors sit where, sensing along
// which axis. Body frame per SAE J211: x forward, y right, z down; positions
// are seismic centres relative to the head CG.
#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/vocabulary.h"

namespace napkin::engine {

enum class SensorKind { kLinear, kAngularRate };

inline constexpr std::array<NamedValue<SensorKind>, 2> kSensorKindNames{
    {{SensorKind::kLinear, "linear"}, {SensorKind::kAngularRate, "angular_rate"}}};
inline constexpr std::array<SensorKind, 2> kSensorKinds = ValuesOf(kSensorKindNames);

// The one spelling of each kind in array JSON ("linear", "angular_rate"), and
// its inverse (nullopt for an unknown name).
constexpr const auto& NamesOf(SensorKind) { return kSensorKindNames; }

struct Sensor {
  std::string slot;  // e.g. "cg_x", "yarm_z", "ars_x"
  SensorKind kind = SensorKind::kLinear;
  Eigen::Vector3d position_body_m = Eigen::Vector3d::Zero();  // from head CG, body axes
  Eigen::Vector3d axis_body = Eigen::Vector3d::UnitX();       // unit sense axis
  std::string unit = "g";                                     // unit of the recorded samples
  // samples * si_per_unit = SI value; 1 g by default (engine/units.h kStandardGravity,
  // which cannot be named here: units.h includes this header).
  double si_per_unit = 9.80665;
};

struct ArrayGeometry {
  std::string name;
  std::string description;
  std::vector<Sensor> sensors;

  // Index of the sensor in `slot`, if any.
  std::optional<std::size_t> FindSlot(std::string_view slot) const;
  std::vector<std::size_t> LinearIndices() const;
  std::vector<std::size_t> RateIndices() const;
  // The linear sensors at the CG (within kAtCgToleranceM of it).
  std::vector<std::size_t> CgLinearIndices() const;
};

// A linear sensor this close to the CG (m) is "at the CG": it reads the CG
// acceleration whatever the rotation (its lever-arm terms are negligible).
inline constexpr double kAtCgToleranceM = 1e-6;

// The 3-2-2-2 slot names in the report's Table 2-1 order.
inline constexpr const char* kNapSlots[9] = {"cg_x",   "cg_y",   "cg_z",   "yarm_z", "yarm_x",
                                             "xarm_z", "xarm_y", "zarm_x", "zarm_y"};

// Throws InvalidArrayError (one sentence naming the problem) when the array
// cannot be solved: no sensors, duplicate slot, zero or non-finite axis or
// position, unknown unit, or neither rotation nor the CG acceleration
// determined (linear rigid-body rank below 6, fewer than 3 independent
// angular-rate axes, and linear sensors at the CG spanning fewer than 3
// directions), ... An array that cannot determine rotation but has a
// triaxial accelerometer at the CG is valid: acceleration only
// (DeterminesRotation, docs/algorithms.md "Acceleration-only arrays").
// Normalises axes in place.
void ValidateArray(ArrayGeometry& array);

// Whether a validated array determines the head's rotation: its linear
// sensors' rigid-body rows have rank 6, or its angular-rate sensors span 3
// axes. False for an acceleration-only array such as 3a-cg (three linear
// accelerometers at the CG), whose results hold the CG acceleration and the
// criteria computed from it, and no rotation.
bool DeterminesRotation(const ArrayGeometry& validated_array);

}  // namespace napkin::engine
