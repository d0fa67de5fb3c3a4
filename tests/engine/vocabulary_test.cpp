// One vocabulary per concept (issue 8): each enum's names have one
// name<->enum pair beside the enum, unit names one parser, and
// ProcessingConfig::Check refuses a setting another one would ignore.
#include <gtest/gtest.h>

#include <array>
#include <cctype>
#include <initializer_list>
#include <numbers>
#include <optional>
#include <string>

#include "common/error.h"
#include "engine/array_geometry.h"
#include "engine/cfc_filter.h"
#include "engine/iso18571.h"
#include "engine/processing.h"
#include "engine/solver.h"
#include "engine/summary.h"
#include "engine/units.h"
#include "synth/synthetic_tests.h"
#include "tests/support/reference_arrays.h"

namespace napkin::engine {
namespace {

// Every value's name parses back to it; an unknown or differently cased
// name does not parse.
template <typename Enum, std::size_t N>
void ExpectRoundTrip(const std::array<Enum, N>& all) {
  const auto parse = [](std::string_view name) { return ParseName<Enum>(name); };
  for (const Enum value : all) {
    const std::string text = NameOf(value);
    EXPECT_EQ(parse(text), value) << text;
    std::string upper = text;
    for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    EXPECT_FALSE(parse(upper)) << upper;
  }
  EXPECT_FALSE(parse(""));
  EXPECT_FALSE(parse("fast"));
}

TEST(Vocabulary, EveryNameParsesBackToItsValue) {
  ExpectRoundTrip(kSolverKinds);
  ExpectRoundTrip(kBiasModes);
  ExpectRoundTrip(kDerivedStorages);
  ExpectRoundTrip(kCfcVariants);
  ExpectRoundTrip(kSeverities);
  ExpectRoundTrip(kSensorKinds);
  ExpectRoundTrip(kIso18571Grades);
  ExpectRoundTrip(kSalvageModes);
  ExpectRoundTrip(kFaultKinds);
  ExpectRoundTrip(kSalvageActions);
}

// Also: every enumerator has its table entry (a missing one would fall back
// to the table's first name).
TEST(Vocabulary, NamesAreTheDocumentedSpellings) {
  EXPECT_STREQ(NameOf(SolverKind::kExact), "exact");
  EXPECT_STREQ(NameOf(SolverKind::kSeed), "seed");
  EXPECT_STREQ(NameOf(BiasMode::kAuto), "auto");
  EXPECT_STREQ(NameOf(BiasMode::kWindow), "window");
  EXPECT_STREQ(NameOf(BiasMode::kNone), "none");
  EXPECT_STREQ(NameOf(SalvageMode::kOff), "off");
  EXPECT_STREQ(NameOf(SalvageMode::kExclude), "exclude");
  EXPECT_STREQ(NameOf(SalvageMode::kRepair), "repair");
  EXPECT_STREQ(NameOf(FaultKind::kDropout), "dropout");
  EXPECT_STREQ(NameOf(FaultKind::kStuck), "stuck");
  EXPECT_STREQ(NameOf(FaultKind::kClipped), "clipped");
  EXPECT_STREQ(NameOf(FaultKind::kSpike), "spike");
  EXPECT_STREQ(NameOf(FaultKind::kFlipped), "flipped");
  EXPECT_STREQ(NameOf(FaultKind::kSwapped), "swapped");
  EXPECT_STREQ(NameOf(FaultKind::kInconsistent), "inconsistent");
  EXPECT_STREQ(NameOf(SalvageAction::kExcluded), "excluded");
  EXPECT_STREQ(NameOf(SalvageAction::kInverted), "inverted");
  EXPECT_STREQ(NameOf(SalvageAction::kSwappedBack), "swapped back");
  EXPECT_STREQ(NameOf(SalvageAction::kReplaced), "replaced");
  EXPECT_STREQ(NameOf(Check::kFault), "fault");
  EXPECT_STREQ(NameOf(Check::kSalvage), "salvage");
  EXPECT_STREQ(NameOf(DerivedStorage::kFloat64), "float64");
  EXPECT_STREQ(NameOf(DerivedStorage::kFloat32), "float32");
  EXPECT_STREQ(NameOf(DerivedStorage::kNone), "none");
  EXPECT_STREQ(NameOf(CfcVariant::kSaeJ211), "sae");
  EXPECT_STREQ(NameOf(CfcVariant::kIso6487), "iso");
  EXPECT_STREQ(NameOf(Severity::kInfo), "info");
  EXPECT_STREQ(NameOf(Severity::kWarning), "warning");
  EXPECT_STREQ(NameOf(Severity::kError), "error");
  EXPECT_STREQ(NameOf(SensorKind::kLinear), "linear");
  EXPECT_STREQ(NameOf(SensorKind::kAngularRate), "angular_rate");
  EXPECT_STREQ(NameOf(Check::kMissing), "missing");
  EXPECT_STREQ(NameOf(Check::kNonFinite), "non_finite");
  EXPECT_STREQ(NameOf(Check::kImplausible), "implausible");
  EXPECT_STREQ(NameOf(Check::kSaturation), "saturation");
  EXPECT_STREQ(NameOf(Check::kSpike), "spike");
  EXPECT_STREQ(NameOf(Check::kBias), "bias");
  EXPECT_STREQ(NameOf(Check::kFlat), "flat");
  EXPECT_STREQ(NameOf(Check::kPolarity), "polarity");
  EXPECT_STREQ(NameOf(Check::kAxisLabel), "axis_label");
  EXPECT_STREQ(NameOf(Check::kResidual), "residual");
  EXPECT_STREQ(NameOf(Check::kConsistency), "consistency");
  EXPECT_STREQ(NameOf(Check::kRotation), "rotation");
}

TEST(Units, OneParserForEverySpelling) {
  // The spellings array JSON accepted before (case-sensitive) ...
  EXPECT_EQ(LinearUnitToSi("g"), kStandardGravity);
  for (const char* unit : {"m/s^2", "m/s2", "m/s**2"}) EXPECT_EQ(LinearUnitToSi(unit), 1.0) << unit;
  EXPECT_EQ(AngularRateUnitToSi("rad/s"), 1.0);
  EXPECT_EQ(AngularRateUnitToSi("deg/s"), std::numbers::pi / 180.0);
  EXPECT_EQ(LengthUnitToMetres("m"), 1.0);
  EXPECT_EQ(LengthUnitToMetres("mm"), 1e-3);
  EXPECT_EQ(LengthUnitToMetres("in"), kMetresPerInch);
  // ... and those of the ISO-MME and UDS-1992 readers.
  EXPECT_EQ(LinearUnitToSi("G'S"), kStandardGravity);
  EXPECT_EQ(LinearUnitToSi("M/SEC**2"), 1.0);
  EXPECT_EQ(LinearUnitToSi("FT/SEC**2"), kMetresPerFoot);
  EXPECT_EQ(LinearUnitToSi("in/s^2"), kMetresPerInch);
  EXPECT_EQ(AngularRateUnitToSi("RADIANS/SECOND"), 1.0);
  EXPECT_EQ(AngularRateUnitToSi("DEG/SEC"), std::numbers::pi / 180.0);
  EXPECT_EQ(AngularRateUnitToSi("\xC2\xB0/s"), std::numbers::pi / 180.0);
  EXPECT_EQ(LengthUnitToMetres("Inches"), kMetresPerInch);
  EXPECT_EQ(LengthUnitToMetres("ft"), kMetresPerFoot);
  // A unit of the other kind, or none, is not a unit of this kind.
  EXPECT_FALSE(LinearUnitToSi("rad/s"));
  EXPECT_FALSE(AngularRateUnitToSi("g"));
  EXPECT_FALSE(LinearUnitToSi("kN"));
  EXPECT_FALSE(SignalUnitToSi("  "));
  EXPECT_FALSE(LengthUnitToMetres("furlong"));
  const std::optional<SignalUnit> rate = SignalUnitToSi("deg/s");
  ASSERT_TRUE(rate);
  EXPECT_EQ(rate->kind, SensorKind::kAngularRate);
}

std::string CheckMessage(const ProcessingConfig& config) {
  try {
    config.Check();
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

void ExpectRefused(const ProcessingConfig& config, std::initializer_list<const char*> fragments) {
  const std::string message = CheckMessage(config);
  ASSERT_FALSE(message.empty()) << "accepted";
  for (const char* fragment : fragments) EXPECT_NE(message.find(fragment), std::string::npos) << message;
}

TEST(ProcessingConfigCheck, RefusesSettingsThatWouldBeIgnored) {
  ProcessingConfig config;
  config.solver = SolverKind::kSeed;
  config.gravity.compensate = true;
  ExpectRefused(config, {"\"gravity.compensate\"", "seed solver", "LC_COMP has no gravity term",
                         "use solver \"exact\" or turn it off"});
  config.solver = SolverKind::kExact;
  EXPECT_EQ(CheckMessage(config), "");

  config = {};
  config.gravity.g_fixed_mps2 = Eigen::Vector3d(0.0, 0.0, 9.81);
  ExpectRefused(config, {"\"gravity.g_fixed\"", "ignored", "gravity.compensate"});
  config.gravity.compensate = true;
  EXPECT_EQ(CheckMessage(config), "");

  for (const BiasMode mode : {BiasMode::kAuto, BiasMode::kNone}) {
    config = {};
    config.bias.mode = mode;
    config.bias.window_start_s = -0.02;
    ExpectRefused(config, {"\"bias.window_s\"", "ignored", NameOf(mode), "\"window\""});
  }
  config.bias.mode = BiasMode::kWindow;
  EXPECT_EQ(CheckMessage(config), "");

  for (const BiasMode mode : {BiasMode::kWindow, BiasMode::kNone}) {
    config = {};
    config.bias.mode = mode;
    config.bias.auto_min_pre_impact_s = 0.005;
    ExpectRefused(config, {"\"bias.auto_min_pre_impact_s\"", "ignored", NameOf(mode), "\"auto\""});
  }

  config = {};
  config.filter.linear_cfc.reset();
  config.filter.angular_rate_cfc.reset();
  EXPECT_EQ(CheckMessage(config), "");
  config.filter.variant = CfcVariant::kIso6487;
  ExpectRefused(config, {"\"filter.variant\"", "ignored", "none"});
  config.filter.variant = CfcVariant::kSaeJ211;
  config.filter.padding_s = 0.02;
  ExpectRefused(config, {"\"filter.padding_s\"", "ignored", "none"});
  config.filter.angular_rate_cfc = kCfc180;
  EXPECT_EQ(CheckMessage(config), "");
}

TEST(Solve, SeedSolverRefusesWhatItWouldIgnore) {
  const synth::SyntheticTest test =
      synth::SynthSeedFixedAxis(test_support::Ideal3222(), Eigen::Vector3d(0.5, 0.5, 0.5));
  SolveOptions options;
  options.solver = SolverKind::kSeed;
  options.initial = test.initial;
  EXPECT_NO_THROW(Solve(test.array, test.signals, options));
  SolveOptions gravity = options;
  gravity.gravity.compensate = true;
  EXPECT_THROW(Solve(test.array, test.signals, gravity), InputError);
  SolveOptions passes = options;
  passes.corrector_passes = 5;
  EXPECT_THROW(Solve(test.array, test.signals, passes), InputError);
}

}  // namespace
}  // namespace napkin::engine
