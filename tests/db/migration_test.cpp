// Schema migrations: embedded list, upgrade in place, failure atomicity.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <optional>
#include <vector>

#include "common/error.h"
#include "db/catalogue.h"
#include "db/float64_blob.h"
#include "db/migrate.h"
#include "engine/criteria.h"
#include "engine/injury_risk.h"
#include "tests/db/db_test_helpers.h"
#include "tests/support/db/catalogue_inspector.h"
#include "tests/support/test_support.h"

namespace napkin::db {
namespace {

using ::testing::HasSubstr;
using ::testing::StrEq;
using ::testing::ThrowsMessage;

// A results row with the columns of schema versions 1 and 2 (before hic_d),
// as a program of those versions wrote it.
void InsertVersion1Result(Catalogue& catalogue, TestId test, ConfigId config, double hic15,
                          std::optional<double> hic36) {
  auto insert = CatalogueInspector(catalogue).connection().Prepare(
      "INSERT INTO results (test_id, config_id, solver, computed_at, hic15, hic15_t1_s, hic15_t2_s, hic36) "
      "VALUES (?1, ?2, 'exact', '2026-01-01T00:00:00Z', ?3, 0.010, 0.025, ?4)");
  insert->Bind(1, test);
  insert->Bind(2, config);
  insert->Bind(3, hic15);
  insert->Bind(4, hic36);
  insert->Execute();
}

std::vector<schema::Migration> EmbeddedPlus(std::vector<schema::Migration> extra) {
  std::vector<schema::Migration> migrations(schema::Migrations().begin(), schema::Migrations().end());
  migrations.insert(migrations.end(), extra.begin(), extra.end());
  return migrations;
}

TEST(Migrations, EmbeddedFilesAreNumberedFromOneWithoutGaps) {
  const auto migrations = schema::Migrations();
  ASSERT_GE(migrations.size(), 2u);
  EXPECT_NO_THROW(CheckMigrationList(migrations));
  EXPECT_EQ(migrations[0].name, "001_catalogue.sql");
  EXPECT_THAT(std::string(migrations[0].sql), HasSubstr("CREATE TABLE tests"));
  EXPECT_THAT(std::string(migrations[1].sql), HasSubstr("CREATE VIEW v_hic"));
}

TEST(Migrations, UpgradeInPlaceKeepsRowsAndBumpsVersion) {
  napkin::test_support::TempDir dir;
  const std::string path = dir / "upgrade.db";
  const auto embedded = schema::Migrations();
  const int k = static_cast<int>(embedded.size());

  std::string tests_before;
  {
    Catalogue catalogue = Catalogue::Open(path);
    ASSERT_EQ(catalogue.schema_version(), k);
    const ArrayId array = catalogue.WriteArray(test_support::IdealArray());
    test_support::AddTest(catalogue, array, "v0001", "sled", "foam-a");
    test_support::AddTest(catalogue, array, "v0002", "sled", "foam-b");
    engine::TestSignals signals;
    signals.slots = {"cg_x"};
    signals.samples = Eigen::MatrixXd::Constant(4, 1, 0.25);
    catalogue.WriteRawChannels(*catalogue.FindTestByExternalId("v0001"), signals,
                               std::vector<std::string>{"g"});
    tests_before = CatalogueInspector(catalogue).Dump();
  }

  // Version k+1, written "in the test": a new column with a default, a new
  // table, and a data fix-up of existing rows.
  const auto migrations =
      EmbeddedPlus({{k + 1, "900_laboratory.sql",
                     "ALTER TABLE tests ADD COLUMN laboratory TEXT NOT NULL DEFAULT 'unknown';"
                     "CREATE TABLE laboratories (id INTEGER PRIMARY KEY, name TEXT UNIQUE);"
                     "INSERT INTO laboratories (name) SELECT DISTINCT laboratory FROM tests;"}});
  CatalogueOptions options;
  options.migrations = migrations;
  Catalogue upgraded = Catalogue::Open(path, options);
  EXPECT_EQ(upgraded.schema_version(), k + 1);
  Connection& connection = CatalogueInspector(upgraded).connection();
  EXPECT_EQ(connection.PragmaInt("user_version"), k + 1);

  const auto tests = upgraded.ReadAllTests();
  ASSERT_EQ(tests.size(), 2u);
  EXPECT_EQ(tests[0].external_id, "v0001");
  EXPECT_EQ(tests[1].variant, "foam-b");
  EXPECT_EQ(upgraded.ReadTestSignals(tests[0].id).samples, Eigen::MatrixXd::Constant(4, 1, 0.25));
  auto laboratory = connection.Prepare("SELECT laboratory, count(*) FROM tests GROUP BY laboratory");
  ASSERT_TRUE(laboratory->Step());
  EXPECT_EQ(laboratory->ColumnText(0), "unknown");
  EXPECT_EQ(laboratory->ColumnInt64(1), 2);
  EXPECT_EQ(connection.PragmaInt("foreign_keys"), 1) << "re-enabled after migrating";

  // Reopening with the same list does nothing more.
  Catalogue again = Catalogue::Open(path, options);
  EXPECT_EQ(again.schema_version(), k + 1);
}

TEST(Migrations, UpgradeFromTheFirstVersionAddsTheViews) {
  napkin::test_support::TempDir dir;
  const std::string path = dir / "v1.db";
  {
    CatalogueOptions first_only;
    first_only.migrations = schema::Migrations().first(1);
    Catalogue catalogue = Catalogue::Open(path, first_only);
    EXPECT_EQ(catalogue.schema_version(), 1);
    const ArrayId array = catalogue.WriteArray(test_support::IdealArray());
    const TestId test = test_support::AddTest(catalogue, array, "v0001", "sled");
    const ConfigId config = catalogue.WriteConfig(test_support::DefaultConfig());
    // The result as this version's program wrote it: the columns of version 1.
    InsertVersion1Result(catalogue, test, config, /*hic15=*/512.5, /*hic36=*/700.0);
    EXPECT_THROW(catalogue.Query(QueryKind::kHic), DatabaseError) << "no views in version 1";
  }
  Catalogue catalogue = Catalogue::Open(path);
  EXPECT_EQ(catalogue.schema_version(), static_cast<int>(schema::Migrations().size()));
  const Table hic = catalogue.Query(QueryKind::kHic);
  ASSERT_EQ(hic.rows.size(), 1u);
  EXPECT_EQ(std::get<std::string>(hic.rows[0][0]), "v0001");
  EXPECT_EQ(std::get<double>(hic.rows[0][3]), 512.5);
  // Version 3 derived hic_d from the stored HIC36 with the engine's arithmetic.
  ASSERT_EQ(hic.columns.back(), "hic_d");
  EXPECT_EQ(std::get<double>(hic.rows[0].back()), engine::HicD(700.0));
  const TestId test = *catalogue.FindTestByExternalId("v0001");
  const auto summary = catalogue.ReadSummary(test, *catalogue.ReadLatestResultConfig(test));
  ASSERT_TRUE(summary.has_value());
  EXPECT_EQ(summary->hic_d, engine::HicD(700.0));
}

TEST(Migrations, UpgradeFromVersion2LeavesResultsWithoutHic36Null) {
  napkin::test_support::TempDir dir;
  const std::string path = dir / "v2.db";
  {
    CatalogueOptions first_two;
    first_two.migrations = schema::Migrations().first(2);
    Catalogue catalogue = Catalogue::Open(path, first_two);
    const ArrayId array = catalogue.WriteArray(test_support::IdealArray());
    const ConfigId config = catalogue.WriteConfig(test_support::DefaultConfig());
    InsertVersion1Result(catalogue, test_support::AddTest(catalogue, array, "with", "sled"), config, 300.0,
                         1234.5);
    InsertVersion1Result(catalogue, test_support::AddTest(catalogue, array, "without", "sled"), config, 300.0,
                         std::nullopt);
  }
  Catalogue catalogue = Catalogue::Open(path);
  const Table hic = catalogue.Query(QueryKind::kHic);
  ASSERT_EQ(hic.rows.size(), 2u);
  EXPECT_EQ(std::get<std::string>(hic.rows[0][0]), "with");
  EXPECT_EQ(std::get<double>(hic.rows[0].back()), 0.75446 * 1234.5 + 166.4);
  EXPECT_TRUE(std::holds_alternative<std::monostate>(hic.rows[1].back()));
}

// Schema 8 gives results computed before it the injury risks of their stored
// criteria, by the engine's curves (schema/008_injury_risk.sql): a NULL BrIC
// (acceleration-only array) and a NULL HIC36 give NULL risks.
TEST(Migrations, UpgradeFromVersion7FillsTheRisksOfTheStoredCriteria) {
  napkin::test_support::TempDir dir;
  const std::string path = dir / "v7.db";
  {
    CatalogueOptions first_seven;
    first_seven.migrations = schema::Migrations().first(7);
    Catalogue catalogue = Catalogue::Open(path, first_seven);
    const ArrayId array = catalogue.WriteArray(test_support::IdealArray());
    const ConfigId config = catalogue.WriteConfig(test_support::DefaultConfig());
    InsertVersion1Result(catalogue, test_support::AddTest(catalogue, array, "rotating", "sled"), config,
                         700.0, 1000.0);
    auto bric = CatalogueInspector(catalogue).connection().Prepare("UPDATE results SET bric = 1.0");
    bric->Execute();
    InsertVersion1Result(catalogue, test_support::AddTest(catalogue, array, "acc-only", "sled"), config,
                         450.0, std::nullopt);
  }
  Catalogue catalogue = Catalogue::Open(path);
  const Table risk = catalogue.Query(QueryKind::kRisk);
  ASSERT_EQ(risk.columns, (std::vector<std::string>{"test_id", "series", "variant", "hic15_p_ais3",
                                                    "hic36_p_ais4", "bric_p_ais3", "bric_p_ais4"}));
  ASSERT_EQ(risk.rows.size(), 2u);
  EXPECT_EQ(std::get<std::string>(risk.rows[0][0]), "acc-only");
  EXPECT_EQ(std::get<double>(risk.rows[0][3]), engine::NcapHic15Ais3Risk(450.0));
  for (std::size_t column = 4; column < 7; ++column)
    EXPECT_TRUE(std::holds_alternative<std::monostate>(risk.rows[0][column])) << column;
  EXPECT_EQ(std::get<std::string>(risk.rows[1][0]), "rotating");
  EXPECT_EQ(std::get<double>(risk.rows[1][3]), engine::NcapHic15Ais3Risk(700.0));
  EXPECT_EQ(std::get<double>(risk.rows[1][4]), engine::PrasadMertzHic36Ais4Risk(1000.0));
  EXPECT_EQ(std::get<double>(risk.rows[1][5]), engine::TakhountsBricAis3Risk(1.0));
  EXPECT_EQ(std::get<double>(risk.rows[1][6]), engine::TakhountsBricAis4Risk(1.0));
}

// Schema 6 rebuilds derived_channels with an encoding column: rows written
// before it are float64 and read back bit for bit.
TEST(Migrations, UpgradeFromVersion5MarksDerivedChannelsFloat64) {
  napkin::test_support::TempDir dir;
  const std::string path = dir / "v5.db";
  const double values[] = {0.1, -2.0 / 3.0};
  TestId test{};
  ConfigId config{};
  {
    CatalogueOptions first_five;
    first_five.migrations = schema::Migrations().first(5);
    Catalogue catalogue = Catalogue::Open(path, first_five);
    const ArrayId array = catalogue.WriteArray(test_support::IdealArray());
    config = catalogue.WriteConfig(test_support::DefaultConfig());
    test = test_support::AddTest(catalogue, array, "old", "sled");
    const std::vector<std::byte> samples = EncodeFloat64LittleEndian(values);
    auto insert = CatalogueInspector(catalogue).connection().Prepare(
        "INSERT INTO derived_channels (test_id, config_id, name, sample_count, samples) "
        "VALUES (?1, ?2, 'omega_body_x_radps', 2, ?3)");
    insert->BindAll(test, config, std::span<const std::byte>(samples));
    insert->Execute();
  }
  Catalogue catalogue = Catalogue::Open(path);
  EXPECT_GE(catalogue.schema_version(), 6);
  auto select = CatalogueInspector(catalogue).connection().Prepare(
      "SELECT encoding, samples FROM derived_channels WHERE test_id = ?1 AND config_id = ?2");
  select->BindAll(test, config);
  ASSERT_TRUE(select->Step());
  EXPECT_EQ(select->ColumnText(0), "float64");
  double decoded[2];
  DecodeFloat64LittleEndian(select->ColumnBlob(1), decoded);
  EXPECT_EQ(decoded[0], values[0]);
  EXPECT_EQ(decoded[1], values[1]);
  EXPECT_FALSE(select->Step());
}

TEST(Migrations, FailedMigrationLeavesThePreviousVersionIntact) {
  napkin::test_support::TempDir dir;
  const std::string path = dir / "fail.db";
  std::string before;
  {
    Catalogue catalogue = Catalogue::Open(path);
    test_support::AddTest(catalogue, catalogue.WriteArray(test_support::IdealArray()), "v0001");
    before = CatalogueInspector(catalogue).Dump();
  }
  const int k = static_cast<int>(schema::Migrations().size());
  // The first statement succeeds, the second fails: the whole migration must roll back.
  const auto migrations =
      EmbeddedPlus({{k + 1, "900_broken.sql",
                     "CREATE TABLE half_done (id INTEGER); INSERT INTO no_such_table VALUES (1);"}});
  CatalogueOptions options;
  options.migrations = migrations;
  EXPECT_THROW(Catalogue::Open(path, options), DatabaseError);

  Catalogue catalogue = Catalogue::Open(path);
  EXPECT_EQ(catalogue.schema_version(), k);
  EXPECT_EQ(CatalogueInspector(catalogue).Dump(), before);
}

TEST(Migrations, MigrationBreakingForeignKeysIsRejected) {
  napkin::test_support::TempDir dir;
  const std::string path = dir / "fk.db";
  {
    Catalogue catalogue = Catalogue::Open(path);
    test_support::AddTest(catalogue, catalogue.WriteArray(test_support::IdealArray()), "v0001");
  }
  const int k = static_cast<int>(schema::Migrations().size());
  const auto migrations = EmbeddedPlus({{k + 1, "900_orphan.sql", "DELETE FROM arrays;"}});
  CatalogueOptions options;
  options.migrations = migrations;
  EXPECT_THAT([&] { Catalogue::Open(path, options); },
              ThrowsMessage<DatabaseError>(HasSubstr("foreign-key violation in table 'tests'")));
  Catalogue catalogue = Catalogue::Open(path);
  EXPECT_EQ(catalogue.ReadAllTests().size(), 1u);
}

TEST(Migrations, NewerCatalogueIsRefused) {
  napkin::test_support::TempDir dir;
  const std::string path = dir / "newer.db";
  const int k = static_cast<int>(schema::Migrations().size());
  {
    CatalogueOptions options;
    const auto migrations = EmbeddedPlus({{k + 1, "900_future.sql", "CREATE TABLE future (id INTEGER);"}});
    options.migrations = migrations;
    Catalogue::Open(path, options);
  }
  EXPECT_THAT(
      [&] { Catalogue::Open(path); },
      ThrowsMessage<InputError>(StrEq("catalogue '" + path + "' has schema version " + std::to_string(k + 1) +
                                      ", newer than this napkin knows (" + std::to_string(k) + ").")));
}

TEST(Migrations, OutdatedCatalogueOpenedReadOnlyAsksForInit) {
  napkin::test_support::TempDir dir;
  const std::string path = dir / "old.db";
  {
    CatalogueOptions first_only;
    first_only.migrations = schema::Migrations().first(1);
    Catalogue::Open(path, first_only);
  }
  CatalogueOptions read_only;
  read_only.read_only = true;
  EXPECT_THAT([&] { Catalogue::Open(path, read_only); },
              ThrowsMessage<InputError>(StrEq(
                  "catalogue '" + path + "' has schema version 1 and needs upgrading with 'napkin init'.")));
}

TEST(Migrations, BadlyNumberedListIsRejected) {
  const std::vector<schema::Migration> gap = {{1, "001_a.sql", "SELECT 1;"}, {3, "003_c.sql", "SELECT 1;"}};
  EXPECT_THROW(CheckMigrationList(gap), std::invalid_argument);
}

}  // namespace
}  // namespace napkin::db
