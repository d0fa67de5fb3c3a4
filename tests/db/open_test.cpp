// Opening catalogues: what is and is not a napkin catalogue, read-only files.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>
#include <thread>

#include "common/error.h"
#include "db/catalogue.h"
#include "db/catalogue_internal.h"
#include "tests/db/db_test_helpers.h"
#include "tests/support/db/catalogue_inspector.h"
#include "tests/support/test_support.h"

namespace napkin::db {
namespace {

using ::testing::StrEq;
using ::testing::ThrowsMessage;

std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

void WriteFile(const std::filesystem::path& path, const std::string& contents) {
  std::ofstream(path, std::ios::binary) << contents;
}

TEST(CatalogueOpen, NewFileIsMigratedToTheLatestSchema) {
  napkin::test_support::TempDir dir;
  const std::string path = dir / "new.db";
  Catalogue catalogue = Catalogue::Open(path);
  Connection& connection = CatalogueInspector(catalogue).connection();
  EXPECT_EQ(catalogue.schema_version(), static_cast<int>(schema::Migrations().size()));
  EXPECT_EQ(connection.PragmaInt("user_version"), catalogue.schema_version());
  EXPECT_EQ(connection.PragmaInt("foreign_keys"), 1);
  EXPECT_EQ(connection.PragmaInt("synchronous"), 2);  // FULL
  auto mode = connection.Prepare("PRAGMA journal_mode");
  ASSERT_TRUE(mode->Step());
  EXPECT_EQ(mode->ColumnText(0), "wal");
}

TEST(CatalogueOpen, InMemoryCatalogueIsPrivateAndComplete) {
  Catalogue first = Catalogue::Open(":memory:");
  Catalogue second = Catalogue::Open(":memory:");
  const ArrayId array = first.WriteArray(test_support::IdealArray());
  test_support::AddTest(first, array, "t1");
  EXPECT_EQ(first.ReadAllTests().size(), 1u);
  EXPECT_TRUE(second.ReadAllTests().empty());
}

TEST(CatalogueOpen, ReopeningKeepsData) {
  napkin::test_support::TempDir dir;
  const std::string path = dir / "keep.db";
  {
    Catalogue catalogue = Catalogue::Open(path);
    test_support::AddTest(catalogue, catalogue.WriteArray(test_support::IdealArray()), "t1", "S", "A");
  }
  Catalogue catalogue = Catalogue::Open(path);
  const auto tests = catalogue.ReadAllTests();
  ASSERT_EQ(tests.size(), 1u);
  EXPECT_EQ(tests[0].external_id, "t1");
  EXPECT_EQ(tests[0].series, "S");
  EXPECT_EQ(tests[0].variant, "A");
}

// A service opens its catalogue again for each batch and checks it once
// (CatalogueOptions::integrity_checked_file): a file checked before is
// opened without reading it whole again; any other file is checked.
TEST(CatalogueOpen, OnlyAFileNotCheckedBeforeIsCheckedAgain) {
  napkin::test_support::TempDir dir;
  const std::string path = dir / "checked.db";
  std::optional<FileIdentity> checked;
  std::int64_t page_size = 0;
  std::int64_t tests_root = 0;
  {
    Catalogue catalogue = Catalogue::Open(path);
    const ArrayId array = catalogue.WriteArray(test_support::IdealArray());
    for (int i = 0; i < 50; ++i) test_support::AddTest(catalogue, array, "t" + std::to_string(i));
    checked = catalogue.file_identity();
    Connection& connection = CatalogueInspector(catalogue).connection();
    page_size = connection.PragmaInt("page_size");
    auto root = connection.Prepare("SELECT rootpage FROM sqlite_master WHERE name = 'tests'");
    ASSERT_TRUE(root->Step());
    tests_root = root->ColumnInt64(0);
  }
  ASSERT_TRUE(checked.has_value());
  {
    // The tests table's root page (its b-tree header) overwritten: quick_check fails.
    std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp((tests_root - 1) * page_size);
    const std::string garbage(64, '\xA5');
    file.write(garbage.data(), static_cast<std::streamsize>(garbage.size()));
  }
  CatalogueOptions options;
  options.check_integrity = true;
  EXPECT_THROW(Catalogue::Open(path, options), InputError) << "not checked before: checked";
  options.integrity_checked_file = FileIdentity{checked->device, checked->inode + 1};
  EXPECT_THROW(Catalogue::Open(path, options), InputError) << "another file was checked";
  options.integrity_checked_file = checked;
  EXPECT_NO_THROW(Catalogue::Open(path, options)) << "checked before: not read again";
}

TEST(CatalogueOpen, TheIntegrityCheckMapsTheFileOnlyWhileItRuns) {
  // db/README.md "Integrity check": quick_check reads a memory-mapped file, and the
  // rest of the command reads through SQLite's read path again.
  napkin::test_support::TempDir dir;
  const std::string path = dir / "mapped.db";
  {
    Catalogue catalogue = Catalogue::Open(path);
    const ArrayId array = catalogue.WriteArray(test_support::IdealArray());
    for (int i = 0; i < 20; ++i) test_support::AddTest(catalogue, array, "t" + std::to_string(i));
  }
  CatalogueOptions options;
  options.check_integrity = true;
  Catalogue catalogue = Catalogue::Open(path, options);
  Connection& connection = CatalogueInspector(catalogue).connection();
  EXPECT_EQ(connection.PragmaInt("main.mmap_size"), 0);
  EXPECT_TRUE(internal::PassesQuickCheck(connection));
  EXPECT_EQ(connection.PragmaInt("main.mmap_size"), 0);
  connection.Execute("PRAGMA main.mmap_size = 65536");
  EXPECT_TRUE(internal::PassesQuickCheck(connection));
  EXPECT_EQ(connection.PragmaInt("main.mmap_size"), 65536) << "a setting of the caller's own is kept";
}

TEST(CatalogueOpen, WriteProtectedFileIsReportedInOneSentence) {
  napkin::test_support::TempDir dir;
  const std::string path = dir / "x.db";
  { Catalogue::Open(path); }
  std::filesystem::permissions(path, std::filesystem::perms::owner_read | std::filesystem::perms::group_read |
                                         std::filesystem::perms::others_read);
  EXPECT_THAT([&] { Catalogue::Open(path); },
              ThrowsMessage<InputError>(StrEq("catalogue '" + path + "' is read-only.")));
  // Opened for queries it works.
  CatalogueOptions read_only;
  read_only.read_only = true;
  Catalogue catalogue = Catalogue::Open(path, read_only);
  EXPECT_TRUE(catalogue.ReadAllTests().empty());
  std::filesystem::permissions(path, std::filesystem::perms::owner_all);
}

TEST(CatalogueOpen, ReadOnlyModeRefusesWrites) {
  napkin::test_support::TempDir dir;
  const std::string path = dir / "ro.db";
  { Catalogue::Open(path); }
  CatalogueOptions read_only;
  read_only.read_only = true;
  Catalogue catalogue = Catalogue::Open(path, read_only);
  EXPECT_THROW(catalogue.WriteArray(test_support::IdealArray()), DatabaseError);
}

TEST(CatalogueOpen, TextFileIsNotASqliteDatabase) {
  napkin::test_support::TempDir dir;
  for (const std::string& contents :
       {std::string("time_s,cg_x\n0.0,1.0\n"), std::string(4096, 'z'), std::string("SQLite format 2")}) {
    const std::string path = dir / "x.db";
    WriteFile(path, contents);
    EXPECT_THAT([&] { Catalogue::Open(path); },
                ThrowsMessage<InputError>(
                    StrEq("'" + path + "' is not a napkin catalogue (not an SQLite database).")));
    EXPECT_EQ(ReadFile(path), contents) << "the file must be left untouched";
  }
}

TEST(CatalogueOpen, OtherApplicationsDatabaseIsRefusedAndUntouched) {
  napkin::test_support::TempDir dir;
  const std::string path = dir / "other.db";
  {
    Connection other = Connection::Open(path);
    other.Execute(
        "CREATE TABLE photos (id INTEGER PRIMARY KEY, name TEXT); INSERT INTO photos VALUES (1, 'a')");
  }
  const std::string before = ReadFile(path);
  EXPECT_THAT([&] { Catalogue::Open(path); },
              ThrowsMessage<InputError>(
                  StrEq("'" + path + "' is not a napkin catalogue (it already holds other tables).")));
  EXPECT_EQ(ReadFile(path), before);

  // Versioned by another application: user_version set, foreign application id.
  {
    Connection other = Connection::Open(path);
    other.Execute("PRAGMA user_version = 1");
  }
  EXPECT_THAT(
      [&] { Catalogue::Open(path); },
      ThrowsMessage<InputError>(
          StrEq("'" + path + "' is not a napkin catalogue (it is another application's SQLite database).")));
}

TEST(CatalogueOpen, MissingFileInReadOnlyModeIsReported) {
  napkin::test_support::TempDir dir;
  const std::string path = dir / "absent.db";
  CatalogueOptions read_only;
  read_only.read_only = true;
  EXPECT_THAT([&] { Catalogue::Open(path, read_only); },
              ThrowsMessage<InputError>(
                  StrEq("cannot open catalogue '" + path + "' (unable to open database file).")));
  EXPECT_FALSE(std::filesystem::exists(path));
}

// Issue 29 point 12: a read-only Catalogue (the read commands, the Python
// Catalogue) leaves the folder as it found it: no -wal or -shm file after it
// closes, and the file unchanged; those of a writer still open stay.
TEST(CatalogueOpen, ReadingLeavesNoLogOrIndexBehind) {
  napkin::test_support::TempDir dir;
  const std::string path = dir / "c.db";
  Catalogue::Open(path).WriteSeries("sled", "");
  ASSERT_FALSE(std::filesystem::exists(path + "-wal"));
  CatalogueOptions read_only;
  read_only.read_only = true;
  {
    Catalogue reader = Catalogue::Open(path, read_only);
    EXPECT_TRUE(reader.ReadSeries("sled").has_value());
    EXPECT_THROW(reader.WriteSeries("other", ""), DatabaseError);
  }
  EXPECT_FALSE(std::filesystem::exists(path + "-wal"));
  EXPECT_FALSE(std::filesystem::exists(path + "-shm"));
  {
    Catalogue writer = Catalogue::Open(path);
    writer.WriteSeries("other", "");
    {
      Catalogue reader = Catalogue::Open(path, read_only);
      EXPECT_TRUE(reader.ReadSeries("other").has_value());
    }
    EXPECT_TRUE(std::filesystem::exists(path + "-wal"));
    EXPECT_TRUE(std::filesystem::exists(path + "-shm"));
  }
  Catalogue reader = Catalogue::Open(path, read_only);
  EXPECT_FALSE(reader.ReadSeries("nope").has_value());
}

// Issue 29 point 7: a named pipe, a folder or a device is refused at once
// (the pipe's open does not block), in one sentence naming it.
TEST(CatalogueOpen, ANamedPipeFolderOrDeviceIsRefused) {
  napkin::test_support::TempDir dir;
  const std::string fifo = dir / "f";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  CatalogueOptions read_only;
  read_only.read_only = true;
  for (const CatalogueOptions& options : {CatalogueOptions{}, read_only}) {
    EXPECT_THAT([&] { Catalogue::Open(fifo, options); },
                ThrowsMessage<InputError>(StrEq(
                    "catalogue '" + fifo +
                    "' is a named pipe (FIFO), not a file; give the name of a regular file, or a name not "
                    "yet taken.")));
    EXPECT_THAT([&] { Catalogue::Open(dir.path().string(), options); },
                ThrowsMessage<InputError>(::testing::HasSubstr("is a directory, not a file")));
    EXPECT_THAT([&] { Catalogue::Open("/dev/null", options); },
                ThrowsMessage<InputError>(::testing::HasSubstr("is a character device, not a file")));
  }
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), {}), 1);
}

// While another connection reads, the automatic checkpoint cannot start the
// write-ahead log again from its beginning, so it grows by what is written;
// RestartWalIfLonger restarts it once the reader has moved on (the next
// write then starts at the beginning: the log is short again).
TEST(CatalogueWal, ALongLogIsRestartedOnceTheReaderHasMovedOn) {
  test_support::TempDir dir;
  const std::string path = dir / "wal.db";
  Catalogue catalogue = Catalogue::Open(path);
  const ArrayId array = catalogue.WriteArray(test_support::IdealArray());
  EXPECT_FALSE(catalogue.RestartWalIfLonger(1 << 20));  // short
  sqlite3* reader = nullptr;
  ASSERT_EQ(sqlite3_open_v2(path.c_str(), &reader, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(reader, "BEGIN; SELECT count(*) FROM tests;", nullptr, nullptr, nullptr), SQLITE_OK);
  engine::TestSignals signals;
  signals.dt_s = 1e-4;
  signals.slots = {"cg_x", "cg_y"};
  signals.samples = Eigen::MatrixXd::Random(100000, 2);  // 1.6 MB
  for (int t = 0; t < 3; ++t) {
    const TestId test = test_support::AddTest(catalogue, array, "t" + std::to_string(t));
    catalogue.WriteRawChannels(test, signals, std::vector<std::string>{"g", "g"});
  }
  // The reader's next transaction starts on a snapshot inside the log (as
  // run's reader always is) and ends a little later, on another thread.
  ASSERT_EQ(sqlite3_exec(reader, "COMMIT; BEGIN; SELECT count(*) FROM tests;", nullptr, nullptr, nullptr),
            SQLITE_OK);
  {
    Transaction transaction = catalogue.BeginTransaction();
    EXPECT_FALSE(catalogue.RestartWalIfLonger(1 << 20));  // never inside a transaction
  }
  std::thread finish_reading([reader] {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    sqlite3_exec(reader, "COMMIT", nullptr, nullptr, nullptr);
  });
  EXPECT_TRUE(catalogue.RestartWalIfLonger(1 << 20));  // waits for the reader
  catalogue.WriteSeries("after");
  EXPECT_FALSE(catalogue.RestartWalIfLonger(1 << 20));
  finish_reading.join();
  sqlite3_close(reader);
  EXPECT_EQ(catalogue.ReadAllTests().size(), 3u);
  EXPECT_EQ(catalogue.ReadTestSignals(catalogue.ReadAllTests()[2].id).samples, signals.samples);
  Catalogue in_memory = Catalogue::Open(":memory:");
  EXPECT_FALSE(in_memory.RestartWalIfLonger(0));
}

}  // namespace
}  // namespace napkin::db
