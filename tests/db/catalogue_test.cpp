// Catalogue repositories: tests, signals, results, kinematics, queries,
// transactions.
#include "db/catalogue.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "common/error.h"
#include "db/float64_blob.h"
#include "db/job_queue.h"
#include "engine/summary_fields.h"
#include "tests/db/db_test_helpers.h"
#include "tests/support/db/catalogue_inspector.h"
#include "tests/support/test_support.h"

namespace napkin::db {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::IsEmpty;
using ::testing::StrEq;
using ::testing::ThrowsMessage;

bool SameBits(const double* a, const double* b, Eigen::Index n) {
  return n == 0 || std::memcmp(a, b, static_cast<std::size_t>(n) * sizeof(double)) == 0;
}

template <typename Matrix>
bool SameBits(const Matrix& a, const Matrix& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() && SameBits(a.data(), b.data(), a.size());
}

// Doubles from random 64-bit patterns: every class of value appears (NaNs
// with payloads, infinities, subnormals, signed zeros) plus the awkward ones.
void FillWithRandomBits(double* values, Eigen::Index n, std::mt19937_64& random) {
  constexpr double kAwkward[] = {0.0,
                                 -0.0,
                                 std::numeric_limits<double>::infinity(),
                                 -std::numeric_limits<double>::infinity(),
                                 std::numeric_limits<double>::denorm_min(),
                                 std::numeric_limits<double>::max(),
                                 std::numeric_limits<double>::quiet_NaN(),
                                 1.0 / 3.0};
  for (Eigen::Index i = 0; i < n; ++i)
    values[i] = i < 8 ? kAwkward[i] : std::bit_cast<double>(static_cast<std::uint64_t>(random()));
}

class CatalogueTest : public ::testing::Test {
 protected:
  void SetUp() override {
    array_ = catalogue_.WriteArray(test_support::IdealArray());
    config_ = catalogue_.WriteConfig(test_support::DefaultConfig());
  }
  Catalogue catalogue_ = Catalogue::Open(":memory:");
  CatalogueInspector inspector_{catalogue_};
  ArrayId array_{};
  ConfigId config_{};
};

// ------------------------------------------------------------------- tests

TEST_F(CatalogueTest, TestRecordRoundTrips) {
  TestRow test;
  test.external_id = "v0001";
  test.series = "sled-2024";
  test.variant = "foam-a";
  test.metadata_json = R"({"speed_kph":24.1,"dummy":"H3-50"})";
  test.array_id = array_;
  test.initial_state.orientation_rad = {0.1, -0.2, 0.3};
  test.initial_state.velocity_fixed_mps = {6.7, 0.0, -0.5};
  test.initial_state.omega_body_radps = {0.0, 1.5, 0.0};
  test.source_path = "/data/v0001";
  test.content_hash = "abc123";
  const TestId id = catalogue_.WriteTest(test);

  const TestRow read = catalogue_.ReadTest(id);
  EXPECT_EQ(read.id, id);
  EXPECT_EQ(read.external_id, test.external_id);
  EXPECT_EQ(read.series, test.series);
  EXPECT_EQ(read.variant, test.variant);
  EXPECT_EQ(read.metadata_json, test.metadata_json);
  EXPECT_EQ(read.array_id, array_);
  EXPECT_EQ(read.initial_state.orientation_rad, test.initial_state.orientation_rad);
  EXPECT_EQ(read.initial_state.velocity_fixed_mps, test.initial_state.velocity_fixed_mps);
  EXPECT_EQ(read.initial_state.omega_body_radps, test.initial_state.omega_body_radps);
  EXPECT_EQ(read.source_path, test.source_path);
  EXPECT_EQ(read.content_hash, test.content_hash);
  EXPECT_THAT(read.imported_at, ::testing::MatchesRegex("[0-9]{4}-[0-9]{2}-[0-9]{2}T[0-9:.]{12}Z"));
  EXPECT_TRUE(catalogue_.ExistsTestByHash("abc123"));
  EXPECT_FALSE(catalogue_.ExistsTestByHash("abc124"));
  EXPECT_TRUE(catalogue_.ExistsTestByExternalId("v0001"));
  EXPECT_EQ(catalogue_.FindTestByExternalId("v0001"), id);
  EXPECT_EQ(catalogue_.FindTestByExternalId("v0002"), std::nullopt);
  ASSERT_TRUE(catalogue_.ReadSeries("sled-2024").has_value());
}

TEST_F(CatalogueTest, DuplicateTestsAreRefusedInOneSentence) {
  test_support::AddTest(catalogue_, array_, "v0001");
  TestRow same_id;
  same_id.external_id = "v0001";
  same_id.array_id = array_;
  same_id.source_path = "/elsewhere/v0001.csv";
  same_id.content_hash = "different";
  EXPECT_THAT([&] { catalogue_.WriteTest(same_id); },
              ThrowsMessage<InputError>(
                  StrEq("test 'v0001' is already in the catalogue (imported from '/data/v0001.csv').")));
  TestRow same_content = same_id;
  same_content.external_id = "copy";
  same_content.content_hash = "content-v0001";
  EXPECT_THAT([&] { catalogue_.WriteTest(same_content); },
              ThrowsMessage<InputError>(StrEq(
                  "'/elsewhere/v0001.csv' has the same content as test 'v0001', already in the catalogue.")));
  TestRow bad_metadata = same_id;
  bad_metadata.external_id = "v0003";
  bad_metadata.metadata_json = "[1, 2]";
  EXPECT_THAT([&] { catalogue_.WriteTest(bad_metadata); },
              ThrowsMessage<InputError>(StrEq("metadata of test 'v0003' is not a JSON object.")));
  EXPECT_EQ(catalogue_.ReadAllTests().size(), 1u);
}

TEST_F(CatalogueTest, ArraysAndConfigsAreDeduplicatedByHash) {
  EXPECT_EQ(catalogue_.WriteArray(test_support::IdealArray()), array_);
  EXPECT_EQ(catalogue_.WriteConfig(test_support::DefaultConfig()), config_);
  const ConfigId other = catalogue_.WriteConfig(test_support::DefaultConfig(R"({"filter":"cfc180"})"));
  EXPECT_NE(other, config_);
  EXPECT_EQ(catalogue_.FindConfigByHash(test_support::DefaultConfig().config_hash), config_);
  EXPECT_EQ(catalogue_.ReadConfig(other).config_json, R"({"filter":"cfc180"})");
  EXPECT_EQ(catalogue_.ReadArray(array_).definition_json, test_support::IdealArray().definition_json);

  ArrayRow collision = test_support::IdealArray();
  collision.definition_json = "{}";
  EXPECT_THROW(catalogue_.WriteArray(collision), InputError);
}

// Values are bound, never spliced into SQL: hostile labels are just labels.
TEST_F(CatalogueTest, HostileNamesRoundTripAndQueryCorrectly) {
  const std::string hostile_series = "x'); DROP TABLE tests;--";
  const std::string hostile_variant = "\" OR 1=1 --";
  const std::string hostile_id = "v'0001\"; DELETE FROM results; --";
  const TestId hostile =
      test_support::AddTest(catalogue_, array_, hostile_id, hostile_series, hostile_variant);
  const TestId plain = test_support::AddTest(catalogue_, array_, "plain", "other", "A");
  engine::TestSummary summary;
  summary.hic15 = {700.0, 0.01, 0.02};
  catalogue_.WriteResult(hostile, config_, summary, "exact");
  summary.hic15 = {300.0, 0.01, 0.02};
  catalogue_.WriteResult(plain, config_, summary, "exact");

  ASSERT_EQ(catalogue_.ReadAllTests().size(), 2u) << "table tests must still exist";
  const auto by_series = catalogue_.ReadAllTests({{hostile_series}, {}, {}});
  ASSERT_EQ(by_series.size(), 1u);
  EXPECT_EQ(by_series[0].external_id, hostile_id);
  EXPECT_EQ(by_series[0].series, hostile_series);
  EXPECT_EQ(by_series[0].variant, hostile_variant);
  EXPECT_EQ(catalogue_.ReadAllTests({{}, {hostile_variant}, {}}).size(), 1u);
  EXPECT_EQ(catalogue_.ReadAllTests({{}, {}, {hostile_id}}).size(), 1u);
  EXPECT_EQ(catalogue_.ReadSeries(hostile_series)->name, hostile_series);

  const Table hic = catalogue_.Query(QueryKind::kHic, TestFilter{{hostile_series}, {}, {}});
  ASSERT_EQ(hic.rows.size(), 1u);
  EXPECT_EQ(std::get<std::string>(hic.rows[0][0]), hostile_id);
  EXPECT_EQ(std::get<std::string>(hic.rows[0][1]), hostile_series);
  EXPECT_EQ(std::get<double>(hic.rows[0][3]), 700.0);
  EXPECT_EQ(catalogue_.Query(QueryKind::kHic).rows.size(), 2u) << "results intact";
}

// ----------------------------------------------------------------- signals

TEST_F(CatalogueTest, SignalsRoundTripBitExact) {
  const TestId test = test_support::AddTest(catalogue_, array_, "v0001");
  std::mt19937_64 random(42);
  engine::TestSignals signals;
  signals.dt_s = 1.0 / 12500.0;  // not representable exactly: must survive as is
  signals.t0_s = -0.0123456789;
  // Deliberately not alphabetical: column order must be kept.
  signals.slots = {"zarm_y", "cg_x", "ars_x", "yarm_z"};
  signals.samples.resize(1001, 4);
  FillWithRandomBits(signals.samples.data(), signals.samples.size(), random);
  const std::vector<std::string> units = {"g", "g", "deg/s", "m/s^2"};
  catalogue_.WriteRawChannels(test, signals, units);

  const engine::TestSignals read = catalogue_.ReadTestSignals(test);
  EXPECT_EQ(std::bit_cast<std::uint64_t>(read.dt_s), std::bit_cast<std::uint64_t>(signals.dt_s));
  EXPECT_EQ(std::bit_cast<std::uint64_t>(read.t0_s), std::bit_cast<std::uint64_t>(signals.t0_s));
  EXPECT_EQ(read.slots, signals.slots);
  EXPECT_TRUE(SameBits(read.samples, signals.samples));

  const auto info = catalogue_.ReadRawChannelInfo(test);
  ASSERT_EQ(info.size(), 4u);
  EXPECT_EQ(info[2].slot, "ars_x");
  EXPECT_EQ(info[2].unit, "deg/s");
  EXPECT_EQ(info[2].sample_count, 1001);

  // The stored BLOB is little-endian float64 whatever the host: check one
  // sample's bytes independently of the codec.
  auto blob = inspector_.connection().Prepare(
      "SELECT samples FROM raw_channels WHERE test_id = ?1 AND slot = 'cg_x'");
  blob->Bind(1, test);
  ASSERT_TRUE(blob->Step());
  const auto bytes = blob->ColumnBlob(0);
  ASSERT_EQ(bytes.size(), 1001u * 8u);
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(signals.samples(500, 1));
  for (int b = 0; b < 8; ++b)
    EXPECT_EQ(static_cast<std::uint64_t>(bytes[500 * 8 + b]), (bits >> (8 * b)) & 0xff) << "byte " << b;
}

TEST_F(CatalogueTest, RewritingSignalsReplacesTheChannels) {
  const TestId test = test_support::AddTest(catalogue_, array_, "v0001");
  engine::TestSignals signals;
  signals.slots = {"a", "b", "c"};
  signals.samples = Eigen::MatrixXd::Ones(10, 3);
  catalogue_.WriteRawChannels(test, signals, std::vector<std::string>(3, "g"));
  signals.slots = {"c"};
  signals.samples = Eigen::MatrixXd::Zero(0, 1);
  catalogue_.WriteRawChannels(test, signals, std::vector<std::string>(1, "g"));
  const engine::TestSignals read = catalogue_.ReadTestSignals(test);
  EXPECT_THAT(read.slots, ElementsAre("c"));
  EXPECT_EQ(read.samples.rows(), 0);
}

// Messages name a test by the id the user gave it, never by its internal row
// number (issue 11 item 10: "test #7").
TEST_F(CatalogueTest, MessagesNameTestsByTheirIdNotTheirRowNumber) {
  test_support::AddTest(catalogue_, array_, "first");
  const TestId test = test_support::AddTest(catalogue_, array_, "v0042");
  engine::TestSignals signals;
  signals.slots = {"a"};
  signals.samples = Eigen::MatrixXd::Ones(10, 1);
  signals.dt_s = std::numeric_limits<double>::infinity();
  try {
    catalogue_.WriteRawChannels(test, signals, std::vector<std::string>(1, "g"));
    FAIL() << "an infinite sampling interval was stored";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("test 'v0042'"), std::string::npos) << message;
    EXPECT_EQ(message.find('#'), std::string::npos) << message;
  }
  try {
    catalogue_.ReadTest(TestId{static_cast<std::int64_t>(test) + 1000});
    FAIL() << "a missing test was read";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()).find('#'), std::string::npos) << error.what();
  }
}

// -------------------------------------------------------------- kinematics

engine::Kinematics RandomKinematics(Eigen::Index n, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  engine::Kinematics kinematics;
  kinematics.Resize(n);
  for (Eigen::Index k = 0; k < n; ++k) kinematics.time_s[k] = 0.001 + static_cast<double>(k) * 1e-4;
  for (auto* series :
       {&kinematics.omega_body, &kinematics.alpha_body, &kinematics.omega_fixed, &kinematics.alpha_fixed,
        &kinematics.acc_body, &kinematics.acc_fixed, &kinematics.vel_fixed, &kinematics.pos_fixed,
        &kinematics.roll_pitch_yaw_rad, &kinematics.dcos_rad})
    FillWithRandomBits(series->data(), series->size(), random);
  FillWithRandomBits(kinematics.quat_fixed_from_body.data(), kinematics.quat_fixed_from_body.size(), random);
  FillWithRandomBits(kinematics.residual.data(), kinematics.residual.size(), random);
  return kinematics;
}

void ExpectSameKinematics(const engine::Kinematics& a, const engine::Kinematics& b) {
  EXPECT_TRUE(SameBits(a.time_s, b.time_s));
  EXPECT_TRUE(SameBits(a.omega_body, b.omega_body));
  EXPECT_TRUE(SameBits(a.alpha_body, b.alpha_body));
  EXPECT_TRUE(SameBits(a.omega_fixed, b.omega_fixed));
  EXPECT_TRUE(SameBits(a.alpha_fixed, b.alpha_fixed));
  EXPECT_TRUE(SameBits(a.acc_body, b.acc_body));
  EXPECT_TRUE(SameBits(a.acc_fixed, b.acc_fixed));
  EXPECT_TRUE(SameBits(a.vel_fixed, b.vel_fixed));
  EXPECT_TRUE(SameBits(a.pos_fixed, b.pos_fixed));
  EXPECT_TRUE(SameBits(a.quat_fixed_from_body, b.quat_fixed_from_body));
  EXPECT_TRUE(SameBits(a.roll_pitch_yaw_rad, b.roll_pitch_yaw_rad));
  EXPECT_TRUE(SameBits(a.dcos_rad, b.dcos_rad));
  EXPECT_TRUE(SameBits(a.residual, b.residual));
}

TEST_F(CatalogueTest, KinematicsRoundTripBitExact) {
  const TestId test = test_support::AddTest(catalogue_, array_, "v0001");
  for (const Eigen::Index n : {Eigen::Index{0}, Eigen::Index{1}, Eigen::Index{777}}) {
    const engine::Kinematics kinematics = RandomKinematics(n, 7 + static_cast<std::uint64_t>(n));
    catalogue_.WriteKinematics(test, config_, kinematics);
    const auto read = catalogue_.ReadKinematics(test, config_);
    ASSERT_TRUE(read.has_value());
    ASSERT_EQ(read->size(), n);
    ExpectSameKinematics(*read, kinematics);
  }
  EXPECT_FALSE(
      catalogue_.ReadKinematics(test, catalogue_.WriteConfig(test_support::DefaultConfig("{}"))).has_value());
}

TEST_F(CatalogueTest, DerivedChannelsAreNamedForPlainSqlite) {
  const TestId test = test_support::AddTest(catalogue_, array_, "v0001");
  catalogue_.WriteKinematics(test, config_, RandomKinematics(11, 3));
  auto names = inspector_.connection().Prepare(
      "SELECT count(*), sum(sample_count = 11), min(dt_s), max(dt_s) FROM derived_channels WHERE test_id = "
      "?1");
  names->Bind(1, test);
  ASSERT_TRUE(names->Step());
  EXPECT_EQ(names->ColumnInt64(0), 1 + 8 * 3 + 4 + 3 + 3 + 1);
  EXPECT_EQ(names->ColumnInt64(1), names->ColumnInt64(0));
  EXPECT_NEAR(names->ColumnDouble(2), 1e-4, 1e-15);
  auto quat = inspector_.connection().Prepare(
      "SELECT 1 FROM derived_channels WHERE name IN ('quat_w', 'omega_fixed_z_radps', 'yaw_rad', "
      "'dcos_xx_rad', "
      "'residual_mps2', 'acc_fixed_x_mps2') GROUP BY test_id HAVING count(*) = 6");
  EXPECT_TRUE(quat->Step());
}

// ----------------------------------------------------------------- results

engine::TestSummary RandomSummary(std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> value(-1000.0, 1000.0);
  engine::TestSummary summary;
  for (const engine::SummaryField& field : engine::SummaryFields()) field.Set(summary, value(random));
  summary.findings = {{"saturation", "cg_x", engine::Severity::kWarning, "Channel cg_x is flat at 200 g."},
                      {"residual", std::nullopt, engine::Severity::kError, "Residual exceeds 5 m/s^2."},
                      {"bias", "yarm_z", engine::Severity::kInfo, "Offset of 0.2 g removed."}};
  return summary;
}

TEST_F(CatalogueTest, SummaryAndFindingsRoundTrip) {
  const TestId test = test_support::AddTest(catalogue_, array_, "v0001");
  EXPECT_FALSE(catalogue_.ReadSummary(test, config_).has_value());
  const engine::TestSummary summary = RandomSummary(1);
  catalogue_.WriteResult(test, config_, summary, "seed");
  const auto read = catalogue_.ReadSummary(test, config_);
  ASSERT_TRUE(read.has_value());
  EXPECT_THAT(engine::DifferingSummaryFields(*read, summary), IsEmpty());
  EXPECT_EQ(read->findings.size(), 3u);
  EXPECT_EQ(inspector_.ReadResultSolver(test, config_), "seed");
}

TEST_F(CatalogueTest, NanSummaryFieldsReadBackAsNan) {
  const TestId test = test_support::AddTest(catalogue_, array_, "v0001");
  engine::TestSummary summary = RandomSummary(2);
  summary.bric = std::numeric_limits<double>::quiet_NaN();
  summary.hic36.value = std::numeric_limits<double>::infinity();
  catalogue_.WriteResult(test, config_, summary, "exact");
  const auto read = catalogue_.ReadSummary(test, config_);
  EXPECT_TRUE(std::isnan(read->bric));
  EXPECT_EQ(read->hic36.value, std::numeric_limits<double>::infinity());
  EXPECT_EQ(read->damage, summary.damage);
}

TEST_F(CatalogueTest, ResultWithoutKinematicsDropsOlderDerivedChannels) {
  const TestId test = test_support::AddTest(catalogue_, array_, "v0001");
  const engine::Kinematics kinematics = RandomKinematics(20, 9);
  catalogue_.WriteResult(test, config_, RandomSummary(3), "exact", &kinematics);
  ASSERT_TRUE(catalogue_.ReadKinematics(test, config_).has_value());
  ExpectSameKinematics(*catalogue_.ReadKinematics(test, config_), kinematics);
  catalogue_.WriteResult(test, config_, RandomSummary(4), "exact");
  EXPECT_FALSE(catalogue_.ReadKinematics(test, config_).has_value());
}

// Storage "float32" (docs/formats.md "Derived-channel storage"): 4 bytes a
// sample, encoding 'float32', and each value read back is exactly the float64
// one rounded to the nearest float.
TEST_F(CatalogueTest, Float32DerivedChannelsHoldEachValueRoundedToFloat) {
  const TestId test = test_support::AddTest(catalogue_, array_, "v0001");
  const engine::Kinematics kinematics = RandomKinematics(301, 12);
  catalogue_.WriteResult(test, config_, RandomSummary(5), "exact", &kinematics,
                         engine::DerivedStorage::kFloat32);
  const auto read = catalogue_.ReadKinematics(test, config_);
  ASSERT_TRUE(read.has_value());
  ASSERT_EQ(read->size(), kinematics.size());
  // The random bits include NaNs (read back as NaN) and values beyond
  // float's range (read back as infinities, as IEEE-754 rounding gives).
  const auto expect_rounded = [](const auto& stored, const auto& exact, const char* member) {
    ASSERT_EQ(stored.size(), exact.size()) << member;
    for (Eigen::Index i = 0; i < exact.size(); ++i) {
      const double rounded = static_cast<double>(static_cast<float>(exact.data()[i]));
      if (std::isnan(rounded))
        ASSERT_TRUE(std::isnan(stored.data()[i])) << member << " element " << i;
      else
        ASSERT_EQ(stored.data()[i], rounded) << member << " element " << i;
    }
  };
  expect_rounded(read->omega_body, kinematics.omega_body, "omega_body");
  expect_rounded(read->alpha_fixed, kinematics.alpha_fixed, "alpha_fixed");
  expect_rounded(read->acc_fixed, kinematics.acc_fixed, "acc_fixed");
  expect_rounded(read->pos_fixed, kinematics.pos_fixed, "pos_fixed");
  expect_rounded(read->quat_fixed_from_body, kinematics.quat_fixed_from_body, "quat_fixed_from_body");
  expect_rounded(read->dcos_rad, kinematics.dcos_rad, "dcos_rad");
  expect_rounded(read->residual, kinematics.residual, "residual");
  // The time base stays float64 (0.001 + k 1e-4 is not a float).
  EXPECT_TRUE(SameBits(read->time_s, kinematics.time_s));

  auto rows = inspector_.connection().Prepare(
      "SELECT count(*), sum(encoding = 'float32'), sum(length(samples) = 4 * 301) FROM derived_channels "
      "WHERE test_id = ?1");
  rows->Bind(1, test);
  ASSERT_TRUE(rows->Step());
  EXPECT_EQ(rows->ColumnInt64(0), 36);
  EXPECT_EQ(rows->ColumnInt64(1), 35);  // all but time_s
  EXPECT_EQ(rows->ColumnInt64(2), 35);

  // Rewritten as float64: bit-exact again, 8 bytes a sample.
  catalogue_.WriteResult(test, config_, RandomSummary(6), "exact", &kinematics,
                         engine::DerivedStorage::kFloat64);
  ExpectSameKinematics(*catalogue_.ReadKinematics(test, config_), kinematics);
  auto encodings = inspector_.connection().Prepare(
      "SELECT sum(encoding = 'float64'), sum(length(samples) = 8 * 301) FROM derived_channels WHERE test_id "
      "= ?1");
  encodings->Bind(1, test);
  ASSERT_TRUE(encodings->Step());
  EXPECT_EQ(encodings->ColumnInt64(0), 36);
  EXPECT_EQ(encodings->ColumnInt64(1), 36);
}

TEST_F(CatalogueTest, StorageNoneKeepsTheSummaryAndDropsOlderDerivedChannels) {
  const TestId test = test_support::AddTest(catalogue_, array_, "v0001");
  const engine::Kinematics kinematics = RandomKinematics(20, 13);
  catalogue_.WriteResult(test, config_, RandomSummary(7), "exact", &kinematics,
                         engine::DerivedStorage::kFloat32);
  ASSERT_TRUE(catalogue_.ReadKinematics(test, config_).has_value());
  const engine::TestSummary summary = RandomSummary(8);
  catalogue_.WriteResult(test, config_, summary, "exact", &kinematics, engine::DerivedStorage::kNone);
  EXPECT_FALSE(catalogue_.ReadKinematics(test, config_).has_value());
  EXPECT_EQ(inspector_.CountRows("derived_channels"), 0);
  const auto read = catalogue_.ReadSummary(test, config_);
  ASSERT_TRUE(read.has_value());
  EXPECT_THAT(engine::DifferingSummaryFields(*read, summary), IsEmpty());
  // WriteKinematics with kNone only removes.
  catalogue_.WriteKinematics(test, config_, kinematics);
  catalogue_.WriteKinematics(test, config_, kinematics, engine::DerivedStorage::kNone);
  EXPECT_FALSE(catalogue_.ReadKinematics(test, config_).has_value());
}

TEST_F(CatalogueTest, SchemaRefusesABlobLengthThatContradictsItsEncoding) {
  const TestId test = test_support::AddTest(catalogue_, array_, "v0001");
  const auto insert = [&](const char* encoding, int bytes_per_sample) {
    auto statement = inspector_.connection().Prepare(
        "INSERT INTO derived_channels (test_id, config_id, name, sample_count, encoding, samples) "
        "VALUES (?1, ?2, ?3, 2, ?4, zeroblob(?5))");
    statement->BindAll(test, config_, std::string("x_") + encoding + std::to_string(bytes_per_sample),
                       std::string(encoding), 2 * bytes_per_sample);
    statement->Execute();
  };
  EXPECT_NO_THROW(insert("float32", 4));
  EXPECT_NO_THROW(insert("float64", 8));
  EXPECT_THROW(insert("float32", 8), DatabaseError);
  EXPECT_THROW(insert("float64", 4), DatabaseError);
  EXPECT_THROW(insert("float16", 2), DatabaseError);
}

// ----------------------------------------------------------------- queries

TEST_F(CatalogueTest, QueryViewsCarryTheContractColumns) {
  using engine::SummaryFieldNames;
  using engine::SummaryGroup;
  std::vector<std::string> hic = {"test_id", "series", "variant"};
  std::vector<std::string> rotation = hic;
  std::vector<std::string> criteria = hic;
  for (const std::string& name : SummaryFieldNames(SummaryGroup::kHic)) hic.push_back(name);
  for (const std::string& name : SummaryFieldNames(SummaryGroup::kRotation)) rotation.push_back(name);
  criteria.insert(criteria.end(), hic.begin() + 3, hic.end());
  criteria.insert(criteria.end(), rotation.begin() + 3, rotation.end());
  EXPECT_EQ(catalogue_.Query(QueryKind::kHic).columns, hic);
  EXPECT_EQ(catalogue_.Query(QueryKind::kRotation).columns, rotation);
  criteria.push_back("salvaged");  // schema/012_salvage.sql
  EXPECT_EQ(catalogue_.Query(QueryKind::kCriteria).columns, criteria);
  EXPECT_EQ(criteria.size(), 3u + 12u + 19u + 1u);  // ubric: schema/015_ubric.sql
  EXPECT_THAT(catalogue_.Query(QueryKind::kQuality).columns,
              ElementsAre("test_id", "series", "variant", "check", "channel", "severity", "detail"));
}

TEST_F(CatalogueTest, QueriesShowEachTestsLatestResultFilteredByLabels) {
  const TestId a1 = test_support::AddTest(catalogue_, array_, "a1", "sled", "A");
  const TestId b1 = test_support::AddTest(catalogue_, array_, "b1", "sled", "B");
  const TestId c1 = test_support::AddTest(catalogue_, array_, "c1", "tower", "A");
  test_support::AddTest(catalogue_, array_, "d1", "sled", "A");  // never processed
  const ConfigId newer = catalogue_.WriteConfig(test_support::DefaultConfig(R"({"filter":"cfc180"})"));

  engine::TestSummary summary = RandomSummary(5);
  summary.hic15.value = 100.0;
  catalogue_.WriteResult(a1, config_, summary, "exact");
  summary.hic15.value = 200.0;
  catalogue_.WriteResult(b1, config_, summary, "exact");
  summary.hic15.value = 300.0;
  catalogue_.WriteResult(c1, config_, summary, "exact");
  summary.hic15.value = 110.0;
  summary.findings.resize(1);
  catalogue_.WriteResult(a1, newer, summary, "exact");  // a1's latest result

  const Table all = catalogue_.Query(QueryKind::kHic);
  ASSERT_EQ(all.rows.size(), 3u);
  EXPECT_EQ(std::get<std::string>(all.rows[0][0]), "a1");
  EXPECT_EQ(std::get<double>(all.rows[0][3]), 110.0);
  EXPECT_EQ(std::get<double>(all.rows[1][3]), 200.0);
  EXPECT_EQ(std::get<double>(all.rows[2][3]), 300.0);

  const Table sled_a = catalogue_.Query(QueryKind::kCriteria, TestFilter{{"sled"}, {"A"}, {}});
  ASSERT_EQ(sled_a.rows.size(), 1u);
  EXPECT_EQ(std::get<std::string>(sled_a.rows[0][0]), "a1");

  const auto summaries = inspector_.ReadAllSummaries({{}, {"A"}, {}});
  ASSERT_EQ(summaries.size(), 2u);
  EXPECT_EQ(summaries[0].test_id, "a1");
  EXPECT_EQ(summaries[0].summary.hic15.value, 110.0);
  EXPECT_EQ(summaries[1].series, "tower");
  EXPECT_EQ(summaries[1].summary.max_residual_mps2, summary.max_residual_mps2);

  // Quality follows the latest result: a1 has one finding under `newer`.
  const Table quality = catalogue_.Query(QueryKind::kQuality);
  ASSERT_EQ(quality.rows.size(), 1u + 3u + 3u);
  EXPECT_EQ(std::get<std::string>(quality.rows[0][0]), "a1");
  EXPECT_EQ(std::get<std::string>(quality.rows[0][3]), "saturation");
  EXPECT_EQ(std::get<std::string>(quality.rows[0][5]), "warning");
  EXPECT_EQ(std::get<std::string>(quality.rows[1][0]), "b1");

  EXPECT_EQ(catalogue_.ReadLatestResultConfig(a1), newer);
  EXPECT_EQ(catalogue_.ReadLatestResultConfig(b1), config_);
  EXPECT_EQ(catalogue_.Query(QueryKind::kTests).rows.size(), 4u);
}

// ------------------------------------------------------------ transactions

TEST_F(CatalogueTest, ExceptionInsideAWriteRollsItBackCompletely) {
  const TestId test = test_support::AddTest(catalogue_, array_, "v0001");
  catalogue_.WriteResult(test, config_, RandomSummary(6), "exact");
  const std::string before = inspector_.Dump();

  // WriteResult replaces the result and findings, then rejects the malformed
  // kinematics: nothing of it may remain.
  engine::Kinematics malformed = RandomKinematics(10, 1);
  malformed.residual.resize(9);
  EXPECT_THROW(catalogue_.WriteResult(test, config_, RandomSummary(7), "exact", &malformed),
               std::invalid_argument);
  EXPECT_EQ(inspector_.Dump(), before);

  // The same write without the fault does change the dump (the check can fail).
  catalogue_.WriteResult(test, config_, RandomSummary(7), "exact");
  EXPECT_NE(inspector_.Dump(), before);
}

TEST_F(CatalogueTest, ExceptionInsideAnOuterTransactionRollsBackEveryWrite) {
  test_support::AddTest(catalogue_, array_, "v0001");
  const std::string before = inspector_.Dump();
  struct Abort {};
  EXPECT_THROW(
      {
        Transaction transaction = catalogue_.BeginTransaction();
        const TestId test = test_support::AddTest(catalogue_, array_, "v0002", "new-series");
        engine::TestSignals signals;
        signals.slots = {"cg_x"};
        signals.samples = Eigen::MatrixXd::Ones(5, 1);
        catalogue_.WriteRawChannels(test, signals, std::vector<std::string>{"g"});
        catalogue_.WriteResult(test, config_, RandomSummary(8), "exact");
        JobQueue(catalogue_).EnqueueMissing(config_);
        throw Abort{};
      },
      Abort);
  EXPECT_EQ(inspector_.Dump(), before);
  EXPECT_FALSE(inspector_.connection().InTransaction());
}

TEST_F(CatalogueTest, FailedInnerWriteRollsBackOnlyItselfInsideACommittedTransaction) {
  Transaction transaction = catalogue_.BeginTransaction();
  test_support::AddTest(catalogue_, array_, "v0001");
  EXPECT_THROW(test_support::AddTest(catalogue_, array_, "v0001"),
               InputError);  // nested savepoint rolled back
  test_support::AddTest(catalogue_, array_, "v0002");
  transaction.Commit();
  const auto tests = catalogue_.ReadAllTests();
  ASSERT_EQ(tests.size(), 2u);
  EXPECT_EQ(tests[1].external_id, "v0002");
}

TEST_F(CatalogueTest, SqliteErrorsNameTheCallAndTheStatement) {
  EXPECT_THAT([&] { inspector_.connection().Execute("INSERT INTO no_such_table VALUES (1)"); },
              ThrowsMessage<DatabaseError>(
                  ::testing::AllOf(HasSubstr("no such table: no_such_table"), HasSubstr("sqlite3_exec"),
                                   HasSubstr("INSERT INTO no_such_table VALUES (1)"))));
}

TEST_F(CatalogueTest, CachedStatementsAreResetAfterAnException) {
  const TestId test = test_support::AddTest(catalogue_, array_, "v0001");
  EXPECT_THROW(catalogue_.ReadTest(TestId{999}), InputError);
  EXPECT_EQ(catalogue_.ReadTest(test).external_id, "v0001");
  // Same statement used again after a throw in the middle of a read.
  EXPECT_THROW(catalogue_.ReadTest(TestId{998}), InputError);
  EXPECT_EQ(catalogue_.ReadTest(test).external_id, "v0001");
}

// -------------------------------------------------------------------- blobs

TEST(Float64Blob, EncodesLittleEndianIeee754) {
  const double values[] = {1.0, -2.0};
  const auto bytes = EncodeFloat64LittleEndian(values);
  ASSERT_EQ(bytes.size(), 16u);
  // 1.0 = 0x3FF0000000000000, -2.0 = 0xC000000000000000, least significant byte first.
  const unsigned char expected[] = {0, 0, 0, 0, 0, 0, 0xF0, 0x3F, 0, 0, 0, 0, 0, 0, 0, 0xC0};
  for (std::size_t i = 0; i < 16; ++i) EXPECT_EQ(static_cast<unsigned>(bytes[i]), expected[i]) << i;
  double decoded[2];
  DecodeFloat64LittleEndian(bytes, decoded);
  EXPECT_EQ(decoded[0], 1.0);
  EXPECT_EQ(decoded[1], -2.0);
  EXPECT_THROW(DecodeFloat64LittleEndian(std::span(bytes).first(15), std::span(decoded, 2)),
               std::invalid_argument);
}

TEST(Float32Blob, EncodesLittleEndianIeee754RoundedToNearest) {
  // 1.0f = 0x3F800000, -2.5f = 0xC0200000; 0.1 rounds to 0x3DCCCCCD.
  const double values[] = {1.0, -2.5, 0.1};
  const auto bytes = EncodeFloat32LittleEndian(values);
  ASSERT_EQ(bytes.size(), 12u);
  const unsigned char expected[] = {0, 0, 0x80, 0x3F, 0, 0, 0x20, 0xC0, 0xCD, 0xCC, 0xCC, 0x3D};
  for (std::size_t i = 0; i < 12; ++i) EXPECT_EQ(static_cast<unsigned>(bytes[i]), expected[i]) << i;
  double decoded[3];
  DecodeFloat32LittleEndian(bytes, decoded);
  EXPECT_EQ(decoded[0], 1.0);
  EXPECT_EQ(decoded[1], -2.5);
  EXPECT_EQ(decoded[2], static_cast<double>(0.1f));
  EXPECT_NE(decoded[2], 0.1);
  EXPECT_THROW(DecodeFloat32LittleEndian(std::span(bytes).first(11), std::span(decoded, 3)),
               std::invalid_argument);
  static_assert(ByteSwap32(0x01020304u) == 0x04030201u);
}

TEST(Float64Blob, ByteSwapReversesBytes) {
  static_assert(ByteSwap64(0x0102030405060708ull) == 0x0807060504030201ull);
  EXPECT_EQ(ByteSwap64(ByteSwap64(0xDEADBEEFCAFEF00Dull)), 0xDEADBEEFCAFEF00Dull);
}

}  // namespace
}  // namespace napkin::db
