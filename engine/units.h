#pragma once
// Unit conversion to SI. The field reports linear accelerations in g
// (1 g = 9.80665 m/s^2, ISO 80000-3 standard gravity); internally everything
// is SI (m, s, rad).
#include <optional>
#include <string_view>

namespace napkin::engine {

inline constexpr double kStandardGravity = 9.80665;  // m/s^2 per g
inline constexpr double kMetresPerInch = 0.0254;
inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kDegPerRad = 180.0 / kPi;

// Factor from the named length unit ("in", "mm", "m") to metres.
std::optional<double> LengthUnitToMetres(std::string_view unit);
// Factor from a linear-acceleration unit ("g", "m/s^2", "m/s2") to m/s^2.
std::optional<double> LinearUnitToSi(std::string_view unit);
// Factor from an angular-rate unit ("rad/s", "deg/s") to rad/s.
std::optional<double> AngularRateUnitToSi(std::string_view unit);

}  // namespace napkin::engine
