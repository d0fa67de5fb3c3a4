#include "engine/units.h"

namespace napkin::engine {

std::optional<double> LengthUnitToMetres(std::string_view unit) {
  if (unit == "m") return 1.0;
  if (unit == "mm") return 1e-3;
  if (unit == "in") return kMetresPerInch;
  return std::nullopt;
}

std::optional<double> LinearUnitToSi(std::string_view unit) {
  if (unit == "g") return kStandardGravity;
  if (unit == "m/s^2" || unit == "m/s2" || unit == "m/s**2") return 1.0;
  return std::nullopt;
}

std::optional<double> AngularRateUnitToSi(std::string_view unit) {
  if (unit == "rad/s") return 1.0;
  if (unit == "deg/s") return kPi / 180.0;
  return std::nullopt;
}

}  // namespace napkin::engine
