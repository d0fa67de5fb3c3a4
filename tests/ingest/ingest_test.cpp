// Ingest: the content hashes existing catalogues hold (pinned byte for
// byte), the one store sequence, and synthetic scenarios into the catalogue.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <new>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "common/error.h"
#include "db/catalogue.h"
#include "formats/array_json.h"
#include "formats/channel_map.h"
#include "formats/csv.h"
#include "formats/isomme.h"
#include "ingest/content_hash.h"
#include "ingest/import.h"
#include "ingest/store.h"
#include "ingest/synthetic_import.h"
#include "records/array_record.h"
#include "tests/formats/formats_test_util.h"
#include "tests/support/db/catalogue_inspector.h"
#include "tests/support/test_support.h"

namespace napkin::ingest {
namespace {

namespace fs = std::filesystem;

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// The expected digests are SHA-256 of the byte sequences the hashes are
// defined by, computed independently (Python hashlib); a change here
// would make existing catalogues import their tests a second time.
TEST(ContentHashTest, SyntheticHashIsPinned) {
  db::ArrayRow array;
  array.definition_hash = "array-hash";
  synth::SyntheticTest test;
  test.signals.slots = {"cg_x", "cg_y"};
  test.signals.dt_s = 1e-4;
  test.signals.t0_s = -0.01;
  test.signals.samples.resize(3, 2);
  test.signals.samples << 1, -4.5, 2, 5.25, 3, 1e300;
  test.initial.orientation_rad = {0.1, 0.2, 0.3};
  test.initial.velocity_fixed_mps = {1.5, -2.5, 3.5};
  test.initial.omega_body_radps = {0.25, -0.5, 0.75};
  EXPECT_EQ(SyntheticContentHash(array, test),
            "33855aa5525cd5ed506085e4f98c2f055d4f01e826f60ea50d2cb1cea753fff3");
}

TEST(ContentHashTest, InputHashesArePinned) {
  napkin::test_support::TempDir dir;
  WriteText(dir / "t.csv", "t,cg_x\n0,1\n");
  WriteText(dir / "v1.001", "first\n");
  WriteText(dir / "v1.002", "second\n");
  ImportInput csv;
  csv.format = InputFormat::kCsv;
  csv.source = dir / "t.csv";
  EXPECT_EQ(InputContentHash(csv), "1bcd17f390aca6eade62177342d9520c0c04f9bc1f3da21a08f40dd710ebc53e");
  ImportInput uds;
  uds.format = InputFormat::kUds1992;
  uds.source = dir / "v1.*";
  uds.files = {dir / "v1.001", dir / "v1.002"};
  EXPECT_EQ(InputContentHash(uds), "ee5c91a9294be5f480fbc7e55baca96fccaea646e995633d6031c61f0f14d191");
}

class StoreTestTest : public ::testing::Test {
 protected:
  StoreTestTest() : catalogue_(db::Catalogue::Open((dir_ / "c.db").string())) {
    synth::RandomMotionOptions motion;
    motion.duration_s = 0.01;
    test_ = synth::SynthRandomMotion(formats::LoadArray("ideal-3222"), motion);
    record_.external_id = "t1";
    record_.initial_state = test_.initial;
    record_.source_path = "synth";
    record_.content_hash = "content-t1";
  }

  napkin::test_support::TempDir dir_;
  db::Catalogue catalogue_;
  synth::SyntheticTest test_;
  db::TestRow record_;
};

TEST_F(StoreTestTest, StoresArrayTestAndChannelsOnceByContent) {
  const db::ArrayRow array = records::MakeArrayRecord(test_.array);
  const std::optional<db::TestId> id = StoreTest(catalogue_, test_.array, array, record_, test_.signals);
  ASSERT_TRUE(id);
  const db::TestRow stored = catalogue_.ReadTest(*id);
  EXPECT_EQ(stored.external_id, "t1");
  EXPECT_EQ(catalogue_.ReadArray(stored.array_id).definition_json, array.definition_json);
  const engine::TestSignals signals = catalogue_.ReadTestSignals(*id);
  EXPECT_EQ(signals.slots, test_.signals.slots);
  EXPECT_EQ(signals.samples, test_.signals.samples);

  // The same content under another id is not stored again.
  const std::string dump = db::CatalogueInspector(catalogue_).Dump();
  db::TestRow again = record_;
  again.external_id = "t2";
  EXPECT_FALSE(StoreTest(catalogue_, test_.array, array, again, test_.signals));
  EXPECT_EQ(db::CatalogueInspector(catalogue_).Dump(), dump);
}

TEST_F(StoreTestTest, AChannelOutsideTheArrayStoresNothing) {
  const std::string dump = db::CatalogueInspector(catalogue_).Dump();
  engine::TestSignals signals = test_.signals;
  signals.slots[1] = "elbow_x";
  try {
    StoreTest(catalogue_, test_.array, records::MakeArrayRecord(test_.array), record_, signals);
    ADD_FAILURE() << "a channel outside the array was stored";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()), "channel 'elbow_x' is not a slot of array 'ideal-3222'.");
  }
  EXPECT_EQ(db::CatalogueInspector(catalogue_).Dump(), dump);
}

TEST(SynthTest, PaddingSeriesIsLabelledDescribedAndStoredOnce) {
  napkin::test_support::TempDir dir;
  db::Catalogue catalogue = db::Catalogue::Open((dir / "c.db").string());
  SynthRequest request;
  request.scenario = synth::SynthScenario::kPaddingSeries;
  EXPECT_EQ(PlanSynth(request).tests.size(), 15u);  // five repeats per padding by default
  request.count = 2;
  request.seed = 7;
  const SynthPlan plan = PlanSynth(request);
  EXPECT_EQ(plan.series, "padding-series");
  ASSERT_EQ(plan.tests.size(), 6u);
  const SynthCounts first = StoreSynthTests(catalogue, plan);
  EXPECT_EQ(first.added, 6);
  EXPECT_EQ(first.present, 0);
  const db::TestRow test = catalogue.ReadTest(*catalogue.FindTestByExternalId("padding-series-foam-a-02"));
  EXPECT_EQ(test.series, "padding-series");
  EXPECT_EQ(test.variant, "foam-a");
  EXPECT_EQ(test.source_path, "synth:padding-series");
  // The fourth test of the series: seed 7 + 3, and the impact drawn from it.
  const synth::HeadImpact impact = synth::ScatteredImpact(synth::kPaddingVariants[1], 10);
  const nlohmann::json expected_impact = {
      {"speed_mps", impact.speed_mps},
      {"trajectory_deg", impact.trajectory_deg},
      {"contact_point_body_m",
       {impact.contact_point_body_m.x(), impact.contact_point_body_m.y(), impact.contact_point_body_m.z()}},
      {"pulse_s", impact.pulse_s},
      {"restitution", 0.15},
      {"noise_g", 0.2},
      {"noise_radps", 0.05}};
  EXPECT_EQ(nlohmann::json::parse(test.metadata_json), (nlohmann::json{{"synthetic",
                                                                        {{"scenario", "padding-series"},
                                                                         {"rate_hz", 10000.0},
                                                                         {"seed", 10},
                                                                         {"impact", expected_impact}}}}));
  EXPECT_NEAR(test.initial_state.velocity_fixed_mps.norm(), impact.speed_mps, 1e-12);
  const SynthCounts second = StoreSynthTests(catalogue, plan);
  EXPECT_EQ(second.added, 0);
  EXPECT_EQ(second.present, 6);
}

TEST(SynthTest, FixedDurationScenariosRefuseSamples) {
  SynthRequest request;
  request.scenario = synth::SynthScenario::kSeedSequential;
  request.duration_s = 0.1;
  try {
    PlanSynth(request);
    ADD_FAILURE() << "--duration accepted for seed-sequential";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              "--samples and --duration apply to the random scenario only; seed-sequential has the report's "
              "fixed duration.");
  }
}

// Issue 11, item 1: an ISO-MME channel declaring an absurd "Number of samples" is refused with
// one sentence naming the file; the good CSV tests of the same folder are imported (the
// partial success the CLI reports with exit status 3, README "import").
TEST(ImportTestsTest, AnAbsurdSampleCountFailsOnlyItsOwnTest) {
  napkin::test_support::TempDir dir;
  const engine::ArrayGeometry array = formats::LoadArray("denton-3222");
  const fs::path folder = dir / "series";
  fs::create_directories(folder);
  formats::WriteSignalsCsv(test_support::MakeSignals(array, 50, 1e-4, 0.0), folder / "a0001.csv");
  formats::WriteSignalsCsv(test_support::MakeSignals(array, 60, 1e-4, 0.0), folder / "a0002.csv");
  formats::WriteIsoMme(test_support::MakeSignals(array, 40, 1e-4, 0.0), array,
                       formats::LoadChannelMap("nap-example"), folder / "m0001", "M0001");
  fs::path spoilt;
  for (const auto& entry : fs::directory_iterator(folder / "m0001" / "Channel"))
    if (entry.path().extension() == ".001") spoilt = entry.path();
  ASSERT_FALSE(spoilt.empty());
  const std::string text = test_support::ReadBytes(spoilt);
  // "Number of samples   :N" -> "Number of samples   :9223372036854775807" (INT64_MAX).
  std::string spoilt_text = text;
  const std::size_t label = spoilt_text.find("Number of samples");
  ASSERT_NE(label, std::string::npos);
  const std::size_t digits = spoilt_text.find(':', label) + 1;
  const std::size_t digits_end = spoilt_text.find_first_not_of("0123456789", digits);
  ASSERT_GT(digits_end, digits);
  spoilt_text.replace(digits, digits_end - digits, "9223372036854775807");
  WriteText(spoilt, spoilt_text);

  db::Catalogue catalogue = db::Catalogue::Open((dir / "c.db").string());
  ImportOptions options;
  options.array = "denton-3222";
  options.channel_map = "nap-example";
  const ImportReport report = ImportTests(catalogue, {folder.string()}, options, {});
  EXPECT_EQ(report.imported, 2);
  EXPECT_EQ(report.failed, 1);
  EXPECT_EQ(report.skipped, 0);
  ASSERT_EQ(report.results.size(), 3u);
  int failures = 0;
  for (const ImportResult& result : report.results) {
    if (result.outcome != ImportOutcome::kFailed) {
      EXPECT_TRUE(catalogue.FindTestByExternalId(result.test_id)) << result.test_id;
      continue;
    }
    ++failures;
    EXPECT_EQ(result.test_id, "m0001");
    EXPECT_NE(result.message.find(spoilt.string()), std::string::npos) << result.message;
    EXPECT_NE(result.message.find("declares 9223372036854775807 samples"), std::string::npos)
        << result.message;
    EXPECT_EQ(result.message.find('\n'), std::string::npos) << result.message;
  }
  EXPECT_EQ(failures, 1);
  EXPECT_FALSE(catalogue.FindTestByExternalId("m0001"));
  EXPECT_EQ(report.SummaryLine(), "imported 2 tests, skipped 0 already present, 1 failed.");
}

// Issue 29 point 20: only input errors are a test's fault. A programmer error
// (here std::logic_error, and std::bad_alloc) while a test is stored is no
// property of the test: it stops the import (the CLI reports an internal
// error), the tests stored before it are kept, and a rerun imports the rest.
TEST(ImportTestsTest, AProgrammerErrorStopsTheImportKeepingTheTestsBeforeIt) {
  napkin::test_support::TempDir dir;
  const engine::ArrayGeometry array = formats::LoadArray("denton-3222");
  const fs::path folder = dir / "series";
  fs::create_directories(folder);
  for (int i = 1; i <= 3; ++i)
    formats::WriteSignalsCsv(test_support::MakeSignals(array, 50 + 10 * i, 1e-4, 0.0),
                             folder / ("a000" + std::to_string(i) + ".csv"));
  ImportOptions options;
  options.array = "denton-3222";
  const std::string path = (dir / "c.db").string();
  for (const bool out_of_memory : {false, true}) {
    fs::remove(path);
    // The catalogue's clock runs once per test stored; its second call in
    // the import (storing a0002) fails.
    bool importing = false;
    int calls = 0;
    db::CatalogueOptions broken;
    broken.clock = [&]() -> double {
      if (importing && ++calls == 2) {
        if (out_of_memory) throw std::bad_alloc();
        throw std::logic_error("injected: a broken invariant");
      }
      return 1.7e9;
    };
    {
      db::Catalogue catalogue = db::Catalogue::Open(path, broken);
      importing = true;
      if (out_of_memory)
        EXPECT_THROW(ImportTests(catalogue, {folder.string()}, options, {}), std::bad_alloc);
      else
        EXPECT_THAT(
            [&] { ImportTests(catalogue, {folder.string()}, options, {}); },
            ::testing::ThrowsMessage<std::logic_error>(::testing::StrEq("injected: a broken invariant")));
      EXPECT_TRUE(catalogue.FindTestByExternalId("a0001"));
      EXPECT_FALSE(catalogue.FindTestByExternalId("a0002"));
    }
    db::Catalogue catalogue = db::Catalogue::Open(path);
    const ImportReport again = ImportTests(catalogue, {folder.string()}, options, {});
    EXPECT_EQ(again.SummaryLine(), "imported 2 tests, skipped 1 already present.");
  }
}

}  // namespace
}  // namespace napkin::ingest
