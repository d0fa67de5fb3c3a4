// Every unit spelling docs/formats.md "Unit spellings" lists is accepted,
// with the listed kind and factor (issue 29 point 16: `deg s^-1` was listed
// but refused, because "DEGS" was shortened to "DEG" before "DEGS^-1" was
// tested). The test reads the table itself, so a spelling added to the docs
// is a case here without editing this file.
#include <gtest/gtest.h>

#include <fstream>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "engine/array_geometry.h"
#include "engine/units.h"
#include "tests/support/test_support.h"

namespace napkin::engine {
namespace {

struct ListedSpelling {
  std::string spelling;
  SensorKind kind;
  double si_per_unit;
};

// The rows between the unit-spellings markers: "| kind | factor | `a`, `b` |".
std::vector<ListedSpelling> DocumentedSpellings() {
  std::ifstream docs(test_support::SourceDir() / "docs" / "formats.md");
  std::vector<ListedSpelling> listed;
  bool inside = false;
  for (std::string line; std::getline(docs, line);) {
    if (line.find("<!-- unit-spellings:begin -->") != std::string::npos) inside = true;
    if (line.find("<!-- unit-spellings:end -->") != std::string::npos) break;
    const bool linear = line.rfind("| linear |", 0) == 0;
    if (!inside || (!linear && line.rfind("| angular_rate |", 0) != 0)) continue;
    const SensorKind kind = linear ? SensorKind::kLinear : SensorKind::kAngularRate;
    const std::size_t factor_start = line.find('|', 1) + 1;
    const double factor = std::stod(line.substr(factor_start, line.find('|', factor_start) - factor_start));
    for (std::size_t open = line.find('`'); open != std::string::npos; open = line.find('`', open + 1)) {
      const std::size_t close = line.find('`', open + 1);
      listed.push_back({line.substr(open + 1, close - open - 1), kind, factor});
      open = close;
    }
  }
  return listed;
}

TEST(UnitSpellings, EveryDocumentedSpellingIsAccepted) {
  const std::vector<ListedSpelling> listed = DocumentedSpellings();
  // 4 for g, 38 for lengths per s^2, 17 for angular rates: the table was read.
  ASSERT_GE(listed.size(), 50U) << "docs/formats.md unit-spellings table not found";
  for (const ListedSpelling& unit : listed) {
    const std::optional<SignalUnit> parsed = SignalUnitToSi(unit.spelling);
    if (!parsed) {
      ADD_FAILURE() << "listed spelling '" << unit.spelling << "' is refused";
      continue;
    }
    EXPECT_EQ(parsed->kind, unit.kind) << unit.spelling;
    EXPECT_DOUBLE_EQ(parsed->si_per_unit, unit.si_per_unit) << unit.spelling;
  }
}

TEST(UnitSpellings, DegreesPerSecondWithANegativePower) {
  for (const char* spelling : {"deg s^-1", "DEG S**-1", "deg s-1", "degrees s^-1", "deg sec^-1"}) {
    const std::optional<double> factor = AngularRateUnitToSi(spelling);
    ASSERT_TRUE(factor) << spelling;
    EXPECT_EQ(*factor, std::numbers::pi / 180.0) << spelling;
  }
  // Plural "degs" is degrees; "rad s^-1" stays radians; neither is a length.
  EXPECT_FALSE(LinearUnitToSi("deg s^-1"));
  EXPECT_EQ(AngularRateUnitToSi("DEGS/SEC"), std::numbers::pi / 180.0);
  EXPECT_EQ(AngularRateUnitToSi("rad s^-1"), 1.0);
}

}  // namespace
}  // namespace napkin::engine
