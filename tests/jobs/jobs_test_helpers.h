#pragma once
// Shared pieces of the scheduler tests: catalogues of synthetic tests and the
// processing setup of a run.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "db/catalogue.h"
#include "engine/kinematics.h"
#include "formats/array_json.h"
#include "ingest/store.h"
#include "jobs/scheduler.h"
#include "records/array_record.h"
#include "records/config_record.h"
#include "synth/synthetic_tests.h"

namespace napkin::test_support {

inline records::ResolvedConfig Processing(const engine::ProcessingConfig& config = {}) {
  return records::ResolvedConfig{config, records::MakeConfigRecord(config, "test-config")};
}

inline std::string TestName(int index) {
  char name[16];
  std::snprintf(name, sizeof name, "r%04d", index);
  return name;
}

// Stores `test` as test `external_id` with the array record `array` (by
// default the record of the test's array; content hash from the id: the
// tests here only need unique hashes).
inline db::TestId StoreTest(db::Catalogue& catalogue, const synth::SyntheticTest& test,
                            const std::string& external_id, const std::string& series = "synthetic",
                            const db::ArrayRow* array = nullptr) {
  db::TestRow record;
  record.external_id = external_id;
  record.series = series;
  record.initial_state = test.initial;
  record.source_path = "synth";
  record.content_hash = "synthetic " + external_id;
  return *ingest::StoreTest(catalogue, test.array, array ? *array : records::MakeArrayRecord(test.array),
                            record, test.signals);
}

// `count` random motions of `samples` samples at 10 kHz on the ideal array,
// ids r0000, r0001, ...
inline void AddRandomTests(const std::string& path, int count, int samples = 1000, int first = 0) {
  db::Catalogue catalogue = db::Catalogue::Open(path);
  const engine::ArrayGeometry array = formats::LoadArray("ideal-3222");
  for (int i = first; i < first + count; ++i) {
    synth::RandomMotionOptions options;
    options.seed = 100 + static_cast<std::uint64_t>(i);
    options.duration_s = (samples - 1) / options.synth.rate_hz;
    StoreTest(catalogue, synth::SynthRandomMotion(array, options), TestName(i));
  }
}

// Every series of the kinematics, by name: compared with ==, i.e. bit for bit
// (no NaN is stored in a derived channel of these tests).
inline void ExpectSameKinematics(const engine::Kinematics& stored, const engine::Kinematics& computed,
                                 const std::string& test) {
  ASSERT_GT(stored.time_s.size(), 0) << test;
  EXPECT_EQ(stored.time_s, computed.time_s) << test;
  EXPECT_EQ(stored.omega_body, computed.omega_body) << test;
  EXPECT_EQ(stored.alpha_body, computed.alpha_body) << test;
  EXPECT_EQ(stored.omega_fixed, computed.omega_fixed) << test;
  EXPECT_EQ(stored.alpha_fixed, computed.alpha_fixed) << test;
  EXPECT_EQ(stored.acc_body, computed.acc_body) << test;
  EXPECT_EQ(stored.acc_fixed, computed.acc_fixed) << test;
  EXPECT_EQ(stored.vel_fixed, computed.vel_fixed) << test;
  EXPECT_EQ(stored.pos_fixed, computed.pos_fixed) << test;
  EXPECT_EQ(stored.quat_fixed_from_body, computed.quat_fixed_from_body) << test;
  EXPECT_EQ(stored.roll_pitch_yaw_rad, computed.roll_pitch_yaw_rad) << test;
  EXPECT_EQ(stored.dcos_rad, computed.dcos_rad) << test;
  EXPECT_EQ(stored.residual, computed.residual) << test;
}

}  // namespace napkin::test_support
