#include "formats/lsdyna.h"

#include <gtest/gtest.h>

#include <fstream>
#include <numbers>

#include "engine/units.h"
#include "tests/formats/formats_test_util.h"
#include "tests/support/lsdyna_keyword.h"
#include "tests/support/test_support.h"
#include "util/text.h"

namespace napkin::formats {
namespace {

using test_support::KeywordField;
using test_support::ParsedKeyword;
using test_support::ParseKeyword;
using test_support::TempDir;
using test_support::Trapezoid;

constexpr double kPulse = 0.05;                         // s
constexpr double kPeakVelocity[3] = {3.0, -1.5, 0.75};  // m/s
constexpr double kPeakOmega[3] = {20.0, -35.0, 5.0};    // rad/s

// A haversine velocity pulse v(t) = V sin^2(pi t / T), whose displacement is
// known in closed form: x(t) = V (t/2 - T sin(2 pi t / T) / (4 pi)).
engine::Kinematics PulseKinematics(Eigen::Index n, double t0) {
  engine::Kinematics k;
  k.Resize(n);
  k.quat_fixed_from_body.setZero();
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) * kPulse / static_cast<double>(n - 1);
    k.time_s[i] = t0 + t;
    const double s = std::sin(std::numbers::pi * t / kPulse);
    for (int c = 0; c < 3; ++c) {
      k.vel_fixed(i, c) = kPeakVelocity[c] * s * s;
      k.omega_fixed(i, c) = kPeakOmega[c] * s * s;
      k.pos_fixed(i, c) = kPeakVelocity[c] * (t / 2 - kPulse * std::sin(2 * std::numbers::pi * t / kPulse) /
                                                          (4 * std::numbers::pi));
    }
  }
  return k;
}

TEST(LsDynaTest, FixedWidthCardsReproduceTheMotion) {
  TempDir dir;
  const engine::Kinematics k = PulseKinematics(501, 0.02);
  for (const LsDynaUnits units : {LsDynaUnits::kSi, LsDynaUnits::kEnglish}) {
    LsDynaOptions options;
    options.units = units;
    options.part_id = 42;
    options.first_curve_id = 100;
    const auto path = dir / "head.k";
    WriteLsDynaKeyword(k, path, options);
    const ParsedKeyword parsed = ParseKeyword(path);
    ASSERT_EQ(parsed.curves.size(), 6u);
    const double length_scale = units == LsDynaUnits::kSi ? 1.0 : 1.0 / 0.0254;
    for (int c = 0; c < 3; ++c) {
      const auto& velocity = parsed.curves.at(100 + c);
      ASSERT_EQ(velocity.size(), 501u);
      EXPECT_EQ(velocity.front().first, 0.0);  // time from the first sample
      EXPECT_NEAR(velocity.back().first, kPulse, 1e-15);
      // Integrating the exported velocity gives the known displacement V T / 2.
      const double expected = kPeakVelocity[c] * kPulse / 2 * length_scale;
      EXPECT_NEAR(Trapezoid(velocity), expected, 1e-3 * std::abs(expected));
      EXPECT_NEAR(Trapezoid(velocity), k.pos_fixed(500, c) * length_scale, 1e-3 * std::abs(expected));
      const double expected_angle = kPeakOmega[c] * kPulse / 2;
      EXPECT_NEAR(Trapezoid(parsed.curves.at(103 + c)), expected_angle, 1e-3 * std::abs(expected_angle));
    }
    ASSERT_EQ(parsed.motions.size(), 6u);
    const int dofs[6] = {1, 2, 3, 5, 6, 7};
    for (int i = 0; i < 6; ++i) {
      EXPECT_EQ(parsed.motions[i][0], 42);       // PID
      EXPECT_EQ(parsed.motions[i][1], dofs[i]);  // DOF
      EXPECT_EQ(parsed.motions[i][2], 0);        // VAD = velocity
      EXPECT_EQ(parsed.motions[i][3], 100 + i);  // LCID
      EXPECT_EQ(parsed.motions[i][4], 1.0);      // SF
    }
  }
}

TEST(LsDynaTest, LegacyLcFileLayout) {
  TempDir dir;
  const engine::Kinematics k = PulseKinematics(101, 0.0);
  WriteLcFile(k, dir / "LC_FILE.DAT");
  std::ifstream in(dir / "LC_FILE.DAT");
  std::string line;
  const char* comments[6] = {"c load curve for x velocity",
                             "c load curve for y velocity",
                             "c load curve for z velocity",
                             "c load curve for angular vel. about x axis",
                             "c load curve for angular vel. about y axis",
                             "c load curve for angular vel. about z axis"};
  for (int curve = 0; curve < 6; ++curve) {
    ASSERT_TRUE(std::getline(in, line));
    EXPECT_EQ(line, comments[curve]);
    ASSERT_TRUE(std::getline(in, line));
    EXPECT_EQ(line, " lcd   " + std::to_string(curve + 1) + "    101");  // 1x,'lcd',3x,i1,3x,i4
    std::vector<std::pair<double, double>> points;
    for (int j = 0; j < 101; ++j) {
      ASSERT_TRUE(std::getline(in, line));
      ASSERT_EQ(line.size(), 26u) << line;  // 2(3x,1pe10.3)
      EXPECT_EQ(line.substr(0, 3), "   ");
      EXPECT_EQ(line.substr(13, 3), "   ");
      EXPECT_EQ(line[9], 'E') << line;  // mantissa d.ddd right-aligned, exponent E±dd
      EXPECT_EQ(line[22], 'E') << line;
      points.emplace_back(KeywordField(line, 3, 10), KeywordField(line, 16, 10));
      // 1pe10.3: four significant digits.
      const double expected = curve < 3 ? k.vel_fixed(j, curve) / 0.0254 : k.omega_fixed(j, curve - 3);
      EXPECT_NEAR(points.back().second, expected, 5e-4 * std::abs(expected) + 1e-30);
      EXPECT_NEAR(points.back().first, j * kPulse / 100, 5e-4 * j * kPulse / 100);
    }
    const double expected =
        curve < 3 ? kPeakVelocity[curve] * kPulse / 2 / 0.0254 : kPeakOmega[curve - 3] * kPulse / 2;
    EXPECT_NEAR(Trapezoid(points), expected, 1e-3 * std::abs(expected));
  }
  EXPECT_FALSE(std::getline(in, line));
}

TEST(LsDynaTest, RejectsSingleSampleWithoutLeavingAFile) {
  TempDir dir;
  engine::Kinematics k;
  k.Resize(1);
  test_support::ExpectInputError([&] { WriteLsDynaKeyword(k, dir / "x.k"); },
                                 {"x.k", "fewer than two samples"});
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

}  // namespace
}  // namespace napkin::formats
