// Issue 11, items 5, 9 and 10 (import side): a FIFO named *.csv or a link to
// /dev/zero in an import folder is reported, not read (no hang); a symbolic
// link loop is reported as a loop; test ids, series and variants with
// control characters (a newline, an escape sequence) or of absurd length are
// refused, while the good tests beside them are imported.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <string>

#include "common/error.h"
#include "db/catalogue.h"
#include "formats/array_json.h"
#include "formats/csv.h"
#include "ingest/discovery.h"
#include "ingest/import.h"
#include "tests/formats/formats_test_util.h"
#include "tests/support/test_support.h"

namespace napkin::ingest {
namespace {

namespace fs = std::filesystem;

bool Contains(const std::string& text, const std::string& fragment) {
  return text.find(fragment) != std::string::npos;
}

TEST(HostileImport, FifoAndDevZeroLinkInAFolderAreReportedAndTheGoodTestImported) {
  if (!fs::exists("/dev/zero")) GTEST_SKIP() << "no /dev/zero";
  test_support::TempDir dir;
  const engine::ArrayGeometry array = formats::LoadArray("denton-3222");
  const fs::path folder = dir / "series";
  fs::create_directories(folder);
  formats::WriteSignalsCsv(test_support::MakeSignals(array, 50, 1e-4, 0.0), folder / "a0001.csv");
  ASSERT_EQ(::mkfifo((folder / "pipe.csv").c_str(), 0600), 0);
  fs::create_symlink("/dev/zero", folder / "zero.csv");

  const Discovery discovery = DiscoverInputs({folder.string()});
  ASSERT_EQ(discovery.inputs.size(), 1u);
  EXPECT_EQ(discovery.inputs[0].name, "a0001");
  ASSERT_EQ(discovery.errors.size(), 2u);
  EXPECT_TRUE(Contains(discovery.errors[0], "pipe.csv' is not a regular file")) << discovery.errors[0];
  EXPECT_TRUE(Contains(discovery.errors[1], "zero.csv' is not a regular file")) << discovery.errors[1];

  db::Catalogue catalogue = db::Catalogue::Open((dir / "c.db").string());
  ImportOptions options;
  options.array = "denton-3222";
  const ImportReport report = ImportTests(catalogue, {folder.string()}, options, {});
  EXPECT_EQ(report.imported, 1);
  EXPECT_EQ(report.failed, 2);
  EXPECT_TRUE(catalogue.FindTestByExternalId("a0001"));

  // Given by name, the FIFO is refused too (never opened for reading).
  const Discovery direct = DiscoverInputs({(folder / "pipe.csv").string()});
  EXPECT_TRUE(direct.inputs.empty());
  ASSERT_EQ(direct.errors.size(), 1u);
  EXPECT_TRUE(Contains(direct.errors[0], "not a regular file")) << direct.errors[0];
}

// Issue 11, item 10: a symbolic-link loop was reported as "does not exist".
TEST(HostileImport, SymbolicLinkLoopIsReportedAsALoop) {
  test_support::TempDir dir;
  fs::create_symlink(dir / "b.csv", dir / "a.csv");
  fs::create_symlink(dir / "a.csv", dir / "b.csv");
  const Discovery discovery = DiscoverInputs({(dir / "a.csv").string()});
  ASSERT_EQ(discovery.errors.size(), 1u);
  EXPECT_TRUE(Contains(discovery.errors[0], "a.csv' is a loop of symbolic links")) << discovery.errors[0];
  EXPECT_FALSE(Contains(discovery.errors[0], "does not exist")) << discovery.errors[0];
}

// Issue 11, item 9: ids with a newline or an escape sequence reached
// terminals and export file names; a 100 MB name was stored.
TEST(HostileImport, TestIdsWithControlCharactersAreRefusedOthersImported) {
  test_support::TempDir dir;
  const engine::ArrayGeometry array = formats::LoadArray("denton-3222");
  const fs::path folder = dir / "series";
  fs::create_directories(folder);
  formats::WriteSignalsCsv(test_support::MakeSignals(array, 50, 1e-4, 0.0), folder / "good.csv");
  formats::WriteSignalsCsv(test_support::MakeSignals(array, 51, 1e-4, 0.0), folder / "bad\nid.csv");
  formats::WriteSignalsCsv(test_support::MakeSignals(array, 52, 1e-4, 0.0), folder / "red\x1b[31m.csv");

  db::Catalogue catalogue = db::Catalogue::Open((dir / "c.db").string());
  ImportOptions options;
  options.array = "denton-3222";
  const ImportReport report = ImportTests(catalogue, {folder.string()}, options, {});
  EXPECT_EQ(report.imported, 1);
  EXPECT_EQ(report.failed, 2);
  EXPECT_TRUE(catalogue.FindTestByExternalId("good"));
  EXPECT_FALSE(catalogue.FindTestByExternalId("bad\nid"));
  EXPECT_FALSE(catalogue.FindTestByExternalId("red\x1b[31m"));
  for (const ImportResult& result : report.results) {
    if (result.outcome != ImportOutcome::kFailed) continue;
    EXPECT_TRUE(Contains(result.message, "contains a control character")) << result.message;
    EXPECT_TRUE(Contains(result.message, "\\n") || Contains(result.message, "\\x1b")) << result.message;
  }
}

TEST(HostileImport, SeriesVariantAndTestIdOptionsAreChecked) {
  test_support::TempDir dir;
  const engine::ArrayGeometry array = formats::LoadArray("denton-3222");
  formats::WriteSignalsCsv(test_support::MakeSignals(array, 50, 1e-4, 0.0), dir / "t.csv");
  db::Catalogue catalogue = db::Catalogue::Open((dir / "c.db").string());
  auto refused = [&](ImportOptions options) -> std::string {
    options.array = "denton-3222";
    try {
      ImportTests(catalogue, {(dir / "t.csv").string()}, options, {});
    } catch (const UsageError& error) {
      return error.what();
    }
    return "";
  };
  ImportOptions series;
  series.series = "line\nbreak";
  EXPECT_TRUE(Contains(refused(series), "--series 'line\\nbreak' contains a control character"));
  ImportOptions variant;
  variant.variant = std::string(100'000, 'v');
  EXPECT_TRUE(Contains(refused(variant), "--variant"));
  EXPECT_TRUE(Contains(refused(variant), "100000 bytes long"));
  ImportOptions id;
  id.test_id = "..\x1b";
  EXPECT_TRUE(Contains(refused(id), "--test-id"));
  EXPECT_FALSE(catalogue.FindTestByExternalId("t"));
}

}  // namespace
}  // namespace napkin::ingest
