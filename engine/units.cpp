#include "engine/units.h"

#include <array>
#include <cctype>
#include <numbers>
#include <string>
#include <utility>

namespace napkin::engine {
namespace {

// Every `from` in `text` replaced by `to`, the result built by appending:
// std::string::replace in place here makes GCC 12's Release build warn
// (a false -Wrestrict from libstdc++'s inlined memcpy) in `make demo`.
void ReplaceAll(std::string& text, std::string_view from, std::string_view to) {
  std::string replaced;
  replaced.reserve(text.size());
  std::size_t start = 0;
  for (std::size_t found; (found = text.find(from, start)) != std::string::npos;
       start = found + from.size()) {
    replaced.append(text, start, found - start);
    replaced.append(to);
  }
  replaced.append(text, start);
  text = std::move(replaced);
}

// Canonical spelling: upper case, no blanks or parentheses, '^' for powers,
// short unit names ("M/SEC**2" -> "M/S^2", "Degrees/Second" -> "DEG/S").
std::string Canonical(std::string_view unit) {
  std::string u;
  for (const char c : unit)
    if (!std::isspace(static_cast<unsigned char>(c)) && c != '(' && c != ')')
      u += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  ReplaceAll(u, "**", "^");
  ReplaceAll(u, "\xC2\xB0", "DEG");  // degree sign (UTF-8)
  ReplaceAll(u, "\xB0", "DEG");      // degree sign (ISO-8859-1)
  for (const char* seconds : {"SECONDS", "SECOND", "SECS", "SEC"}) ReplaceAll(u, seconds, "S");
  for (const char* metres : {"METERS", "METRES", "METER", "METRE"}) ReplaceAll(u, metres, "M");
  for (const char* radians : {"RADIANS", "RADIAN"}) ReplaceAll(u, radians, "RAD");
  for (const char* degrees : {"DEGREES", "DEGREE"}) ReplaceAll(u, degrees, "DEG");
  // Plural "degs" only before a '/': in "DEGS^-1" (deg s^-1, blanks gone)
  // the S is the second (issue 29 point 16).
  ReplaceAll(u, "DEGS/", "DEG/");
  ReplaceAll(u, "INCHES", "IN");
  ReplaceAll(u, "INCH", "IN");
  ReplaceAll(u, "FEET", "FT");
  ReplaceAll(u, "FOOT", "FT");
  return u;
}

constexpr std::array<std::pair<std::string_view, double>, 5> kMetresPer{
    {{"M", 1.0}, {"MM", 1e-3}, {"CM", 1e-2}, {"IN", kMetresPerInch}, {"FT", kMetresPerFoot}}};

std::optional<double> CanonicalLengthToMetres(const std::string& u) {
  for (const auto& [name, factor] : kMetresPer)
    if (u == name) return factor;
  return std::nullopt;
}

}  // namespace

std::optional<SignalUnit> SignalUnitToSi(std::string_view unit) {
  const std::string u = Canonical(unit);
  if (u.empty()) return std::nullopt;
  if (u == "G" || u == "G'S" || u == "GS" || u == "GN")
    return SignalUnit{SensorKind::kLinear, kStandardGravity};
  for (const auto& [length, factor] : kMetresPer) {
    const std::string p(length);
    if (u == p + "/S^2" || u == p + "/S2" || u == p + "S^-2" || u == p + "S-2" || u == p + "/S/S")
      return SignalUnit{SensorKind::kLinear, factor};
  }
  if (u == "RAD/S" || u == "RADPS" || u == "RAD/S^1" || u == "RADS^-1" || u == "RADS-1")
    return SignalUnit{SensorKind::kAngularRate, 1.0};
  if (u == "DEG/S" || u == "DEGPS" || u == "DEGS^-1" || u == "DEGS-1" || u == "DPS")
    return SignalUnit{SensorKind::kAngularRate, std::numbers::pi / 180.0};
  return std::nullopt;
}

std::optional<double> LengthUnitToMetres(std::string_view unit) {
  return CanonicalLengthToMetres(Canonical(unit));
}

std::optional<double> LinearUnitToSi(std::string_view unit) {
  const std::optional<SignalUnit> parsed = SignalUnitToSi(unit);
  if (!parsed || parsed->kind != SensorKind::kLinear) return std::nullopt;
  return parsed->si_per_unit;
}

std::optional<double> AngularRateUnitToSi(std::string_view unit) {
  const std::optional<SignalUnit> parsed = SignalUnitToSi(unit);
  if (!parsed || parsed->kind != SensorKind::kAngularRate) return std::nullopt;
  return parsed->si_per_unit;
}

}  // namespace napkin::engine
