#pragma once
// Unit conversion to SI. The field reports linear accelerations in g
// (1 g = 9.80665 m/s^2, ISO 80000-3 standard gravity); internally everything
// is SI (m, s, rad). This is the one place that reads unit names: array
// JSON, ISO-MME and UDS-1992 channels all go through SignalUnitToSi.
#include <numbers>
#include <optional>
#include <string_view>

#include "engine/array_geometry.h"

namespace napkin::engine {

inline constexpr double kStandardGravity = 9.80665;  // m/s^2 per g
inline constexpr double kMetresPerInch = 0.0254;
inline constexpr double kMetresPerFoot = 0.3048;
inline constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// Physical kind and SI factor of a recorded signal's unit.
struct SignalUnit {
  SensorKind kind;
  double si_per_unit;
};

// Unit spellings are read case-insensitively, blanks and parentheses
// ignored, "**" or "^" for powers, long or short names and the degree sign:
// "g", "G'S", "m/s^2", "m/s2", "M/SEC**2", "ft/s^2", "IN/SEC**2", "rad/s",
// "RADIANS/SECOND", "deg/s", "DEG/SEC", "deg s^-1", "°/s", ... (the full
// list: docs/formats.md "Unit spellings"); nullopt for an unknown (or blank)
// spelling.
std::optional<SignalUnit> SignalUnitToSi(std::string_view unit);
// Factor from a length unit (m, mm, cm, in, ft; same spellings) to metres.
std::optional<double> LengthUnitToMetres(std::string_view unit);
// Factor from a linear-acceleration unit (g or length/s^2) to m/s^2.
std::optional<double> LinearUnitToSi(std::string_view unit);
// Factor from an angular-rate unit (rad/s or deg/s) to rad/s.
std::optional<double> AngularRateUnitToSi(std::string_view unit);

}  // namespace napkin::engine
