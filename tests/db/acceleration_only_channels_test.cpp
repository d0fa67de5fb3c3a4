// Derived channels of acceleration-only kinematics (engine::Kinematics::
// ResizeWithoutRotation; docs/formats.md "Derived-channel storage"): only
// time_s and acc_body_* are stored, they read back as acceleration-only
// kinematics (the rest absent, not NaN-filled), results stored before with
// all 36 channels NaN read back as stored, and an incomplete set is refused
// naming the missing channel.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "common/error.h"
#include "db/catalogue.h"
#include "engine/kinematics.h"
#include "tests/db/db_test_helpers.h"
#include "tests/support/db/catalogue_inspector.h"

namespace napkin::db {
namespace {

using ChannelSizes = std::vector<std::pair<std::string, std::int64_t>>;

class AccelerationOnlyChannels : public ::testing::Test {
 protected:
  void SetUp() override {
    array_ = catalogue_.WriteArray(test_support::IdealArray());
    config_ = catalogue_.WriteConfig(test_support::DefaultConfig());
    test_ = test_support::AddTest(catalogue_, array_, "h1");
  }

  // Acceleration-only kinematics of n samples: time from 1 ms at 10 kHz, a smooth CG acceleration.
  static engine::Kinematics AccelerationOnly(Eigen::Index n) {
    engine::Kinematics kinematics;
    kinematics.ResizeWithoutRotation(n);
    for (Eigen::Index k = 0; k < n; ++k) {
      kinematics.time_s[k] = 0.001 + static_cast<double>(k) * 1e-4;
      kinematics.acc_body.row(k) << std::sin(0.01 * static_cast<double>(k)), 2.5,
          -0.125 * static_cast<double>(k);
    }
    return kinematics;
  }

  Catalogue catalogue_ = Catalogue::Open(":memory:");
  CatalogueInspector inspector_{catalogue_};
  ArrayId array_{};
  ConfigId config_{};
  TestId test_{};
};

TEST_F(AccelerationOnlyChannels, StoresTimeAndCgAccelerationOnlyAndReadsThemBack) {
  constexpr Eigen::Index kSamples = 500;
  const engine::Kinematics kinematics = AccelerationOnly(kSamples);
  ASSERT_FALSE(engine::HasRotation(kinematics));
  catalogue_.WriteKinematics(test_, config_, kinematics, engine::DerivedStorage::kFloat64);
  EXPECT_EQ(inspector_.ReadDerivedChannelSizes(test_, config_),
            (ChannelSizes{{"acc_body_x_mps2", 8 * kSamples},
                          {"acc_body_y_mps2", 8 * kSamples},
                          {"acc_body_z_mps2", 8 * kSamples},
                          {"time_s", 8 * kSamples}}));

  const auto read = catalogue_.ReadKinematics(test_, config_);
  ASSERT_TRUE(read.has_value());
  EXPECT_FALSE(engine::HasRotation(*read));
  EXPECT_EQ(read->time_s, kinematics.time_s);
  EXPECT_EQ(read->acc_body, kinematics.acc_body);
  // Absent, not NaN-filled.
  for (const engine::Series3* series :
       {&read->omega_body, &read->alpha_body, &read->omega_fixed, &read->alpha_fixed, &read->acc_fixed,
        &read->vel_fixed, &read->pos_fixed, &read->roll_pitch_yaw_rad, &read->dcos_rad})
    EXPECT_EQ(series->rows(), 0);
  EXPECT_EQ(read->quat_fixed_from_body.rows(), 0);
  EXPECT_EQ(read->residual.rows(), 0);

  // float32: the CG acceleration in 4 bytes a sample, time_s in 8.
  catalogue_.WriteKinematics(test_, config_, kinematics, engine::DerivedStorage::kFloat32);
  EXPECT_EQ(inspector_.ReadDerivedChannelSizes(test_, config_),
            (ChannelSizes{{"acc_body_x_mps2", 4 * kSamples},
                          {"acc_body_y_mps2", 4 * kSamples},
                          {"acc_body_z_mps2", 4 * kSamples},
                          {"time_s", 8 * kSamples}}));
}

TEST_F(AccelerationOnlyChannels, ResultsStoredNaNFilledReadBackAsStored) {
  // How napkin stored an acceleration-only result before: 36 channels, NaN but time and acc_body.
  constexpr Eigen::Index kSamples = 20;
  const engine::Kinematics only = AccelerationOnly(kSamples);
  engine::Kinematics filled;
  filled.Resize(kSamples);
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  for (engine::Series3* series :
       {&filled.omega_body, &filled.alpha_body, &filled.omega_fixed, &filled.alpha_fixed, &filled.acc_fixed,
        &filled.vel_fixed, &filled.pos_fixed, &filled.roll_pitch_yaw_rad, &filled.dcos_rad})
    series->setConstant(kNaN);
  filled.quat_fixed_from_body.setConstant(kNaN);
  filled.residual.setConstant(kNaN);
  filled.time_s = only.time_s;
  filled.acc_body = only.acc_body;
  catalogue_.WriteKinematics(test_, config_, filled, engine::DerivedStorage::kFloat64);
  EXPECT_EQ(inspector_.ReadDerivedChannelSizes(test_, config_).size(), 36u);
  const auto read = catalogue_.ReadKinematics(test_, config_);
  ASSERT_TRUE(read.has_value());
  EXPECT_FALSE(engine::HasRotation(*read));
  EXPECT_EQ(read->acc_body, only.acc_body);
  EXPECT_EQ(read->omega_body.rows(), kSamples);
  EXPECT_TRUE(read->omega_body.array().isNaN().all());
}

TEST_F(AccelerationOnlyChannels, RefusesAnIncompleteSetOrShape) {
  catalogue_.WriteKinematics(test_, config_, AccelerationOnly(30), engine::DerivedStorage::kFloat64);
  inspector_.connection().Execute("DELETE FROM derived_channels WHERE name = 'acc_body_y_mps2'");
  try {
    catalogue_.ReadKinematics(test_, config_);
    FAIL() << "an acceleration-only set without acc_body_y_mps2 was read";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()), "derived channels of test 'h1' lack 'acc_body_y_mps2'.");
  }

  // One rotation series but not the others: neither shape.
  engine::Kinematics mixed = AccelerationOnly(30);
  mixed.omega_body.setZero(30, 3);
  EXPECT_THROW(catalogue_.WriteKinematics(test_, config_, mixed), std::invalid_argument);
}

}  // namespace
}  // namespace napkin::db
