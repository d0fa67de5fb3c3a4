#include "engine/array_geometry.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <ostream>

#include "common/error.h"
#include "engine/array_analysis.h"
#include "engine/exact_solver.h"
#include "tests/support/named_cases.h"
#include "tests/support/reference_arrays.h"

namespace napkin::engine {
namespace {

using ::testing::HasSubstr;

std::string RejectionMessage(ArrayGeometry array) {
  try {
    ValidateArray(array);
  } catch (const InvalidArrayError& error) {
    return error.what();
  }
  return "";
}

// A valid reference array and the exact-solver path it takes.
struct ClassifiedArrayCase {
  const char* name;
  ArrayGeometry (*array)();
  ExactPath path;
};
void PrintTo(const ClassifiedArrayCase& classified, std::ostream* os) { *os << classified.name; }

class ReferenceArrayTest : public ::testing::TestWithParam<ClassifiedArrayCase> {};

TEST_P(ReferenceArrayTest, IsValidAndClassified) {
  ArrayGeometry array = GetParam().array();
  EXPECT_NO_THROW(ValidateArray(array)) << array.name;
  EXPECT_EQ(ClassifyArray(array), GetParam().path);
}

INSTANTIATE_TEST_SUITE_P(
    Reference, ReferenceArrayTest,
    ::testing::Values(
        ClassifiedArrayCase{"ideal_3222", &test_support::Ideal3222, ExactPath::kLinear},
        ClassifiedArrayCase{"volpe_table4_2", &test_support::VolpeTable42, ExactPath::kLinear},
        ClassifiedArrayCase{"denton_3222", &test_support::Denton3222, ExactPath::kLinear},
        ClassifiedArrayCase{"six_a_omega_cg", &test_support::SixAOmegaCg, ExactPath::kSixAOmega},
        ClassifiedArrayCase{"nap_ars12", &test_support::NapArs12, ExactPath::kFused},
        ClassifiedArrayCase{"three_a_cg", &test_support::ThreeACg, ExactPath::kAccelerationOnly}),
    test_support::CaseName());

TEST(ArrayGeometry, SlotLookupAndKinds) {
  const ArrayGeometry array = test_support::NapArs12();
  ASSERT_TRUE(array.FindSlot("xarm_y").has_value());
  EXPECT_EQ(*array.FindSlot("xarm_y"), 6u);
  EXPECT_FALSE(array.FindSlot("nope").has_value());
  EXPECT_EQ(array.LinearIndices(), (std::vector<std::size_t>{0, 1, 2, 3, 4, 5, 6, 7, 8}));
  EXPECT_EQ(array.RateIndices(), (std::vector<std::size_t>{9, 10, 11}));
}

TEST(ArrayGeometry, NormalisesAxes) {
  ArrayGeometry array = test_support::Ideal3222();
  array.sensors[4].axis_body = Eigen::Vector3d(3.0, 0.0, 4.0);
  ValidateArray(array);
  EXPECT_NEAR(array.sensors[4].axis_body.norm(), 1.0, 1e-15);
  EXPECT_NEAR(array.sensors[4].axis_body.x(), 0.6, 1e-15);
}

// A malformed array (mostly the ideal 3-2-2-2 with one sensor spoilt) and
// what ValidateArray's message must say.
struct MalformedArrayCase {
  const char* name;
  ArrayGeometry (*make)();
  const char* message;
};
void PrintTo(const MalformedArrayCase& malformed, std::ostream* os) { *os << malformed.name; }

// The ideal 3-2-2-2 whose cg_x sensor has an unknown unit with this factor.
ArrayGeometry UnknownUnit(double factor) {
  ArrayGeometry bad_unit = test_support::Ideal3222();
  bad_unit.sensors[0].unit = "furlong/fortnight^2";
  bad_unit.sensors[0].si_per_unit = factor;
  return bad_unit;
}

class MalformedArrayTest : public ::testing::TestWithParam<MalformedArrayCase> {};

TEST_P(MalformedArrayTest, IsRejected) {
  EXPECT_THAT(RejectionMessage(GetParam().make()), HasSubstr(GetParam().message));
}

INSTANTIATE_TEST_SUITE_P(
    Sensors, MalformedArrayTest,
    ::testing::Values(MalformedArrayCase{"empty",
                                         [] {
                                           ArrayGeometry empty;
                                           empty.name = "foo";
                                           return empty;
                                         },
                                         "array 'foo' has no sensors"},
                      MalformedArrayCase{"duplicate_slot",
                                         [] {
                                           ArrayGeometry duplicate = test_support::Ideal3222();
                                           duplicate.sensors[3].slot = "cg_x";
                                           return duplicate;
                                         },
                                         "slot 'cg_x' appears more than once"},
                      MalformedArrayCase{"unnamed_slot",
                                         [] {
                                           ArrayGeometry unnamed = test_support::Ideal3222();
                                           unnamed.sensors[2].slot.clear();
                                           return unnamed;
                                         },
                                         "sensor 3 has an empty slot name"},
                      MalformedArrayCase{"zero_axis",
                                         [] {
                                           ArrayGeometry zero_axis = test_support::Ideal3222();
                                           zero_axis.sensors[5].axis_body.setZero();
                                           return zero_axis;
                                         },
                                         "slot 'xarm_z' has a zero or non-finite sense axis"},
                      MalformedArrayCase{"nan_axis",
                                         [] {
                                           ArrayGeometry nan_axis = test_support::Ideal3222();
                                           nan_axis.sensors[5].axis_body.x() =
                                               std::numeric_limits<double>::quiet_NaN();
                                           return nan_axis;
                                         },
                                         "slot 'xarm_z' has a zero or non-finite sense axis"},
                      MalformedArrayCase{"infinite_position",
                                         [] {
                                           ArrayGeometry nan_position = test_support::Ideal3222();
                                           nan_position.sensors[7].position_body_m.z() =
                                               std::numeric_limits<double>::infinity();
                                           return nan_position;
                                         },
                                         "slot 'zarm_x' has a non-finite position"},
                      MalformedArrayCase{"unknown_unit_zero_factor", [] { return UnknownUnit(0.0); },
                                         "slot 'cg_x' has unknown unit 'furlong/fortnight^2'"},
                      MalformedArrayCase{"unknown_unit_negative_factor", [] { return UnknownUnit(-9.8); },
                                         "slot 'cg_x' has unknown unit 'furlong/fortnight^2'"},
                      MalformedArrayCase{"unknown_unit_nan_factor",
                                         [] { return UnknownUnit(std::numeric_limits<double>::quiet_NaN()); },
                                         "slot 'cg_x' has unknown unit 'furlong/fortnight^2'"}),
    test_support::CaseName());

TEST(ArrayGeometry, RejectsUnsolvableGeometries) {
  // All nine at one point off the CG: alpha is invisible (rank 3 of 6) and
  // no sensor reads the CG acceleration (the point's own includes the
  // unknown centripetal term).
  ArrayGeometry at_one_point = test_support::Ideal3222();
  at_one_point.name = "foo";
  for (Sensor& sensor : at_one_point.sensors) sensor.position_body_m = Eigen::Vector3d(0.05, 0.0, 0.0);
  const std::string message = RejectionMessage(at_one_point);
  EXPECT_THAT(message,
              HasSubstr("array 'foo': the linear sensors do not determine the six rigid-body "
                        "accelerations (rank 3 of 6), and the linear sensors at the CG span only 0 "
                        "of 3 directions, so neither rotation nor the CG acceleration is determined"));
  EXPECT_THAT(message, HasSubstr("add sensors off the CG, angular-rate sensors, or a triaxial accelerometer "
                                 "at the CG."));

  // Only five sensors can never reach rank 6: the five arm sensors, none at the CG.
  ArrayGeometry five_arms = test_support::Ideal3222();
  five_arms.sensors.erase(five_arms.sensors.begin(), five_arms.sensors.begin() + 3);
  five_arms.sensors.resize(5);
  EXPECT_THAT(RejectionMessage(five_arms), HasSubstr("rank 5 of 6"));

  // Without the z arm the 3-2-2-2 still senses alpha_x (yarm_z), alpha_y
  // (xarm_z) and alpha_z (yarm_x, xarm_y); dropping yarm_z as well leaves
  // nothing with a lever arm for alpha_x, and without cg_x the sensors at the
  // CG span two directions only.
  ArrayGeometry no_z_arm = test_support::Ideal3222();
  no_z_arm.sensors.resize(7);
  EXPECT_EQ(RejectionMessage(no_z_arm), "");
  ArrayGeometry no_alpha_x = no_z_arm;
  no_alpha_x.sensors.erase(no_alpha_x.sensors.begin() + 3);  // yarm_z
  no_alpha_x.sensors.erase(no_alpha_x.sensors.begin());      // cg_x
  EXPECT_THAT(RejectionMessage(no_alpha_x), HasSubstr("rank 5 of 6"));
  EXPECT_THAT(RejectionMessage(no_alpha_x), HasSubstr("at the CG span only 2 of 3 directions"));

  // 3 accelerometers off the CG + only 2 rate axes.
  ArrayGeometry two_rates = test_support::SixAOmegaCg();
  for (int i = 0; i < 3; ++i) two_rates.sensors[i].position_body_m = Eigen::Vector3d(0.05, 0.0, 0.0);
  two_rates.sensors.pop_back();
  EXPECT_THAT(RejectionMessage(two_rates), HasSubstr("angular-rate sensors span only 2 of 3 axes"));

  // 3 rate axes but two parallel accelerometers: the CG acceleration is undetermined.
  ArrayGeometry parallel = test_support::SixAOmegaCg();
  parallel.sensors[1].axis_body = Eigen::Vector3d::UnitX();
  EXPECT_THAT(RejectionMessage(parallel), HasSubstr("linear sense axes span only 2 of 3 directions"));

  // Rate sensors along two axes only, even with many of them (accelerometers off the CG).
  ArrayGeometry coplanar_rates = test_support::SixAOmegaCg();
  for (int i = 0; i < 3; ++i) coplanar_rates.sensors[i].position_body_m = Eigen::Vector3d(0.0, 0.0, 0.05);
  coplanar_rates.sensors[5].axis_body = Eigen::Vector3d(1.0, 1.0, 0.0);
  EXPECT_THAT(RejectionMessage(coplanar_rates), HasSubstr("span only 2 of 3 axes"));
}

// docs/algorithms.md "Acceleration-only arrays": an array that cannot
// determine rotation but has linear sensors at the CG along three
// independent axes is valid, and said not to determine rotation.
TEST(ArrayGeometry, AcceptsAccelerationOnlyArrays) {
  // All nine at the CG (alpha invisible, rank 3 of 6): the CG triad reads a.
  ArrayGeometry at_cg = test_support::Ideal3222();
  for (Sensor& sensor : at_cg.sensors) sensor.position_body_m.setZero();
  // The first five of the 3-2-2-2 (rank 5 of 6); three CG accelerometers
  // with only two rate axes; the 3a-cg triad alone; a skewed CG triad.
  ArrayGeometry five = test_support::Ideal3222();
  five.sensors.resize(5);
  ArrayGeometry two_rates = test_support::SixAOmegaCg();
  two_rates.sensors.pop_back();
  ArrayGeometry skewed = test_support::ThreeACg();
  skewed.sensors[0].axis_body = Eigen::Vector3d(1.0, 1.0, 0.0);
  for (ArrayGeometry array : {at_cg, five, two_rates, test_support::ThreeACg(), skewed}) {
    SCOPED_TRACE(array.sensors.size());
    EXPECT_EQ(RejectionMessage(array), "");
    ValidateArray(array);
    EXPECT_FALSE(DeterminesRotation(array));
    EXPECT_EQ(ClassifyArray(array), ExactPath::kAccelerationOnly);
  }
  // Arrays that determine rotation say so.
  for (ArrayGeometry array :
       {test_support::Ideal3222(), test_support::SixAOmegaCg(), test_support::NapArs12()}) {
    ValidateArray(array);
    EXPECT_TRUE(DeterminesRotation(array)) << array.name;
  }
  // A sensor a micrometre or more from the CG is not at the CG.
  ArrayGeometry off_cg = test_support::ThreeACg();
  off_cg.sensors[2].position_body_m = Eigen::Vector3d(0.0, 0.0, 2e-6);
  EXPECT_THAT(RejectionMessage(off_cg), HasSubstr("at the CG span only 2 of 3 directions"));
}

TEST(ArrayGeometry, RankIsIndependentOfLengthUnitScale) {
  // The same NAP shrunk 1000x is still solvable (the rank test scales the
  // alpha columns by the lever arm).
  ArrayGeometry tiny = test_support::Denton3222();
  for (Sensor& sensor : tiny.sensors) sensor.position_body_m *= 1e-3;
  EXPECT_NO_THROW(ValidateArray(tiny));
}

}  // namespace
}  // namespace napkin::engine
