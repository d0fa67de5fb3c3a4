// `napkin init`: creates a catalogue, migrates an older one in place without
// losing rows, and is a no-op on an up-to-date one; says which.
#include <gtest/gtest.h>

#include <vector>

#include "schema/migrations.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"

namespace napkin::cli {

using namespace napkin::test_support;
namespace {

const int kLatest = static_cast<int>(schema::Migrations().size());

TEST(CliInit, CreatesThenReportsUpToDateWithoutChangingAnything) {
  napkin::test_support::TempDir dir;
  const RunResult created = RunNapkin(dir.path(), {"init"});
  EXPECT_EQ(created.exit_code, 0) << created.err;
  EXPECT_EQ(created.out, "created catalogue 'napkin.db' (schema version " + std::to_string(kLatest) + ").\n");
  EXPECT_EQ(created.err, "");
  ASSERT_TRUE(fs::exists(dir / "napkin.db"));
  EXPECT_EQ(OpenForReading(dir / "napkin.db").schema_version(), kLatest);
  const std::string dump = DumpCatalogue(dir / "napkin.db");

  const RunResult again = RunNapkin(dir.path(), {"--db", "napkin.db", "init"});
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(again.out,
            "catalogue 'napkin.db' is up to date (schema version " + std::to_string(kLatest) + ").\n");
  EXPECT_EQ(DumpCatalogue(dir / "napkin.db"), dump);
}

TEST(CliInit, MigratesAnOlderCatalogueInPlaceKeepingItsRows) {
  napkin::test_support::TempDir dir;
  const fs::path path = dir / "old.db";
  // A catalogue written by an earlier build that knew only migration 1.
  const std::vector<schema::Migration> first_only(schema::Migrations().begin(),
                                                  schema::Migrations().begin() + 1);
  engine::TestSignals signals;
  signals.dt_s = 1e-4;
  signals.slots = {"cg_x", "cg_y"};
  signals.samples.resize(5, 2);
  signals.samples << 0.5, -1.25, 1e-300, 3.0, -0.0, 7.5, 1.0 / 3.0, 2.0, 9.75, -8.5;
  {
    db::CatalogueOptions options;
    options.migrations = first_only;
    db::Catalogue old = db::Catalogue::Open(path.string(), options);
    ASSERT_EQ(old.schema_version(), 1);
    const db::ArrayId array = old.WriteArray({{}, "two", R"({"name":"two"})", "hash-two"});
    for (const char* id : {"v0001", "v0002"}) {
      db::TestRow test;
      test.external_id = id;
      test.series = "sled";
      test.variant = std::string("foam-") + id;
      test.array_id = array;
      test.source_path = std::string("/data/") + id + ".csv";
      test.content_hash = std::string("content-") + id;
      const db::TestId key = old.WriteTest(test);
      old.WriteRawChannels(key, signals, std::vector<std::string>{"g", "g"});
    }
  }

  const RunResult migrated = RunNapkin(dir.path(), {"--db", "old.db", "init"});
  EXPECT_EQ(migrated.exit_code, 0) << migrated.err;
  EXPECT_EQ(migrated.out,
            "migrated catalogue 'old.db' from schema version 1 to " + std::to_string(kLatest) + ".\n");

  db::Catalogue catalogue = OpenForReading(path);
  EXPECT_EQ(catalogue.schema_version(), kLatest);
  const std::vector<db::TestRow> tests = catalogue.ReadAllTests();
  ASSERT_EQ(tests.size(), 2u);
  EXPECT_EQ(tests[0].external_id, "v0001");
  EXPECT_EQ(tests[1].variant, "foam-v0002");
  const engine::TestSignals back = catalogue.ReadTestSignals(tests[1].id);
  EXPECT_EQ(back.slots, signals.slots);
  EXPECT_EQ(back.samples, signals.samples);  // bit-exact
  // The views of migration 2 exist and see the old rows.
  EXPECT_EQ(catalogue.Query(db::QueryKind::kTests).rows.size(), 2u);

  const std::string dump = db::CatalogueInspector(catalogue).Dump();
  const RunResult again = RunNapkin(dir.path(), {"--db", "old.db", "init"});
  EXPECT_EQ(again.exit_code, 0);
  EXPECT_EQ(again.out,
            "catalogue 'old.db' is up to date (schema version " + std::to_string(kLatest) + ").\n");
  EXPECT_EQ(DumpCatalogue(path), dump);
}

TEST(CliInit, RefusesAFileThatIsNotACatalogueAndLeavesItAlone) {
  napkin::test_support::TempDir dir;
  const std::string text = "time_s,cg_x\n0,1\n";
  WriteText(dir / "notes.db", text);
  const RunResult run = RunNapkin(dir.path(), {"--db", "notes.db", "init"});
  EXPECT_EQ(run.exit_code, 1);
  ExpectOneSentenceError(run, {"notes.db", "not a napkin catalogue"});
  EXPECT_EQ(ReadText(dir / "notes.db"), text);
}

}  // namespace
}  // namespace napkin::cli
