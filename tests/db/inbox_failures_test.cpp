// The inbox's failures of tests that never became tests of the catalogue
// (schema/016_inbox_failures.sql; docs/formats.md "Inbox failures"): stored,
// replaced by a newer one, removed, and carried by merge.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "db/catalogue.h"
#include "tests/db/db_test_helpers.h"
#include "tests/support/test_support.h"

namespace napkin::db {
namespace {

InboxFailure SidecarFailure(const std::string& source, const std::string& signature) {
  InboxFailure failure;
  failure.source = source;
  failure.test_name = std::filesystem::path(source).stem().string();
  failure.series = "s";
  failure.variant = "typo";
  failure.kind = "sidecar";
  failure.error = "sidecar 'in/s/typo/napkin.json' key 'config': \"defualt\" is neither a file nor a preset.";
  failure.signature = signature;
  return failure;
}

TEST(InboxFailures, AreStoredReplacedAndRemovedBySource) {
  CatalogueOptions options;
  double now_s = 1.8e9;
  options.clock = [&] { return now_s; };
  Catalogue catalogue = Catalogue::Open(":memory:", options);
  EXPECT_TRUE(catalogue.ReadInboxFailures().empty());
  catalogue.WriteInboxFailure(SidecarFailure("in/s/typo/t2.csv", "sig-a"));
  catalogue.WriteInboxFailure(SidecarFailure("in/s/typo/t1.csv", "sig-b"));
  const std::optional<InboxFailure> read = catalogue.ReadInboxFailure("in/s/typo/t2.csv");
  ASSERT_TRUE(read.has_value());
  EXPECT_EQ(read->test_name, "t2");
  EXPECT_EQ(read->series, "s");
  EXPECT_EQ(read->variant, "typo");
  EXPECT_EQ(read->kind, "sidecar");
  EXPECT_EQ(read->error, SidecarFailure("", "").error);
  EXPECT_EQ(read->signature, "sig-a");
  EXPECT_EQ(read->failed_at, "2027-01-15T08:00:00.000Z");
  // The latest failure of a source replaces its earlier one.
  now_s += 60;
  InboxFailure newer = SidecarFailure("in/s/typo/t2.csv", "sig-c");
  newer.kind = "import failed";
  newer.error = "test 'in/s/typo/t2.csv' could not be imported: row 3 has 2 columns.";
  catalogue.WriteInboxFailure(newer);
  const std::vector<InboxFailure> all = catalogue.ReadInboxFailures();
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].source, "in/s/typo/t1.csv");  // by source
  EXPECT_EQ(all[1].kind, "import failed");
  EXPECT_EQ(all[1].error, newer.error);
  EXPECT_EQ(all[1].signature, "sig-c");
  EXPECT_EQ(all[1].failed_at, "2027-01-15T08:01:00.000Z");
  catalogue.DeleteInboxFailure("in/s/typo/t2.csv");
  catalogue.DeleteInboxFailure("in/s/typo/never-failed.csv");
  ASSERT_EQ(catalogue.ReadInboxFailures().size(), 1u);
  EXPECT_FALSE(catalogue.ReadInboxFailure("in/s/typo/t2.csv").has_value());
}

TEST(InboxFailures, ACheckRefusesAnotherKind) {
  Catalogue catalogue = Catalogue::Open(":memory:");
  InboxFailure failure = SidecarFailure("in/s/a/t1.csv", "sig");
  failure.kind = "screening";
  EXPECT_THROW(catalogue.WriteInboxFailure(failure), DatabaseError);
}

// A service's catalogue merged into another keeps what its inbox could not import: rows of tests
// the catalogue lacks, the newer of two of one source; merging again adds nothing.
TEST(InboxFailures, MergeCarriesThemForTestsTheCatalogueLacks) {
  test_support::TempDir dir;
  const std::string main_path = (dir.path() / "main.db").string();
  const std::string shard_path = (dir.path() / "service.db").string();
  double now_s = 1.8e9;
  CatalogueOptions options;
  options.clock = [&] { return now_s; };
  {
    Catalogue main = Catalogue::Open(main_path, options);
    const ArrayId array = main.WriteArray(test_support::IdealArray());
    test_support::AddTest(main, array, "t9", "s", "a");
    main.WriteInboxFailure(SidecarFailure("in/s/typo/t1.csv", "old"));
  }
  const std::string imported_source = "/data/t9.csv";  // AddTest's
  {
    now_s += 10;
    Catalogue shard = Catalogue::Open(shard_path, options);
    shard.WriteInboxFailure(SidecarFailure("in/s/typo/t1.csv", "new"));
    shard.WriteInboxFailure(SidecarFailure("in/s/typo/t2.csv", "sig"));
    // A failure of a test the catalogue has imported since is history: not carried.
    shard.WriteInboxFailure(SidecarFailure(imported_source, "stale"));
  }
  Catalogue main = Catalogue::Open(main_path, options);
  EXPECT_EQ(main.MergeShard(shard_path).inbox_failures_merged, 2);
  const std::vector<InboxFailure> merged = main.ReadInboxFailures();
  ASSERT_EQ(merged.size(), 2u);
  EXPECT_EQ(merged[0].signature, "new");
  EXPECT_EQ(merged[1].source, "in/s/typo/t2.csv");
  EXPECT_EQ(main.MergeShard(shard_path).inbox_failures_merged, 0);
}

}  // namespace
}  // namespace napkin::db
