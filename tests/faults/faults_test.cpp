// Fault injection (issue 11): the napkin binary against SIGKILL during import
// and run, two imports and two runs at once, a full file system, read-only
// catalogue files and directories, a corrupted page, a file that is not
// SQLite, and a merge of the catalogue into itself under every spelling of
// its name. Each case ends with one clear error line or a complete result,
// and the catalogue passes PRAGMA integrity_check with no duplicated or
// partial rows.
//
// NAPKIN_FAULTS_BINARY=/path/to/napkin runs the cases against another build
// (e.g. an older main, to see which defects it has).
#include <gtest/gtest.h>
#include <pwd.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "db/catalogue.h"
#include "formats/csv.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/db/catalogue_inspector.h"
#include "tests/support/run_command.h"
#include "tests/support/test_support.h"

namespace napkin {
namespace {

namespace fs = std::filesystem;
using test_support::CommandResult;
using test_support::ExpectOneSentenceError;
using test_support::Lines;
using test_support::ReadText;

std::string NapkinBinary() {
  const char* other = std::getenv("NAPKIN_FAULTS_BINARY");
  return other != nullptr && *other != '\0' ? other : NAPKIN_BINARY;
}

std::vector<std::string> Concat(std::vector<std::string> head, const std::vector<std::string>& tail) {
  head.insert(head.end(), tail.begin(), tail.end());
  return head;
}

// The one integer `sql` answers.
std::int64_t Scalar(db::CatalogueInspector& inspector, const std::string& sql) {
  auto statement = inspector.connection().Prepare(sql);
  return statement->Step() ? statement->ColumnInt64(0) : -1;
}

// The first line of PRAGMA integrity_check ("ok" when the file is sound).
std::string IntegrityCheck(const fs::path& path) {
  db::Catalogue catalogue = test_support::OpenForReading(path);
  auto check = db::CatalogueInspector(catalogue).connection().Prepare("PRAGMA integrity_check");
  return check->Step() ? check->ColumnText(0) : "no answer";
}

// A sound catalogue with no duplicated or partial rows: every test has its
// nine raw channels, ids are unique, every result has its done job and 36
// derived channels, every done job its result.
void ExpectSound(const fs::path& path, const std::string& when) {
  ASSERT_EQ(IntegrityCheck(path), "ok") << when;
  db::Catalogue catalogue = test_support::OpenForReading(path);
  db::CatalogueInspector inspector(catalogue);
  EXPECT_EQ(Scalar(inspector,
                   "SELECT count(*) FROM tests AS t WHERE "
                   "(SELECT count(*) FROM raw_channels AS r WHERE r.test_id = t.id) <> 9"),
            0)
      << when;
  EXPECT_EQ(Scalar(inspector, "SELECT count(*) - count(DISTINCT external_id) FROM tests"), 0) << when;
  const std::int64_t results = inspector.CountRows("results");
  EXPECT_EQ(results, inspector.CountTestsWithResults()) << when;
  EXPECT_EQ(results, inspector.CountJobsInState("done")) << when;
  EXPECT_EQ(inspector.CountResultsWithoutDoneJob(), 0) << when;
  EXPECT_EQ(inspector.CountRows("derived_channels"), results * 36) << when;
  EXPECT_EQ(inspector.CountIncompleteOrOrphanDerivedChannelSets(36), 0) << when;
}

std::int64_t CountRowsOrZero(const fs::path& path, const std::string& table) {
  try {
    db::Catalogue catalogue = test_support::OpenForReading(path);
    return db::CatalogueInspector(catalogue).CountRows(table);
  } catch (const std::exception&) {
    return 0;  // not created yet, or a writer holds a lock for a moment
  }
}

class Faults : public ::testing::Test {
 protected:
  CommandResult Napkin(const std::vector<std::string>& args) {
    return test_support::RunProgram(NapkinBinary(), args, dir_.path());
  }
  pid_t Start(const std::vector<std::string>& args, const std::string& name) {
    return test_support::StartProgram(NapkinBinary(), args, dir_ / (name + ".out"), dir_ / (name + ".err"),
                                      dir_.path());
  }
  CommandResult Finished(pid_t pid, const std::string& name) {
    CommandResult result;
    result.exit_code = test_support::WaitProgram(pid);
    result.out = ReadText(dir_ / (name + ".out"));
    result.err = ReadText(dir_ / (name + ".err"));
    return result;
  }
  void Synth(const std::string& db, int count, int samples) {
    const CommandResult synth = Napkin({"--db", db, "synth", "--scenario", "random", "--count",
                                        std::to_string(count), "--samples", std::to_string(samples)});
    ASSERT_EQ(synth.exit_code, 0) << synth.err;
  }
  // `count` distinct small CSV tests (100 samples at 10 kHz) in `folder`.
  void WriteCsvTests(const fs::path& folder, int count) {
    fs::create_directories(folder);
    const synth::SyntheticTest base = test_support::SynthNapTest(71, 0.01);
    for (int i = 0; i < count; ++i) {
      engine::TestSignals signals = base.signals;
      signals.samples.array() += 0.001 * i;
      char name[16];
      std::snprintf(name, sizeof name, "k%03d.csv", i);
      formats::WriteSignalsCsv(signals, folder / name);
    }
  }
  // Kills `pid` (SIGKILL: no clean-up at all) once `table` of `db` has at
  // least `rows` rows; false when the program ended first.
  bool KillAfterRows(pid_t pid, const fs::path& db, const std::string& table, std::int64_t rows) {
    const auto start = std::chrono::steady_clock::now();
    while (CountRowsOrZero(db, table) < rows &&
           std::chrono::steady_clock::now() - start < std::chrono::seconds(60)) {
      int status = 0;
      if (waitpid(pid, &status, WNOHANG) == pid) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    return true;
  }

  test_support::TempDir dir_;
};

// "imported N tests, skipped M already present." -> {N, M} ({-1, -1} otherwise).
std::pair<int, int> ImportCounts(const CommandResult& import) {
  const std::vector<std::string> lines = Lines(import.out);
  if (lines.empty() || lines.back().rfind("imported ", 0) != 0) return {-1, -1};
  const std::string& line = lines.back();
  const std::size_t skipped = line.find("skipped ");
  if (skipped == std::string::npos) return {-1, -1};
  return {std::atoi(line.c_str() + 9), std::atoi(line.c_str() + skipped + 8)};
}

// ----------------------------------------------------- concurrent processes

// Issue 11 item 4: two imports of the same folder at once store each test
// once; each reports the tests the other stored as skipped (exit 0), never as
// failed, also when both create the catalogue.
TEST_F(Faults, TwoImportsOfTheSameFolderAtOnceCountTheOthersTestsAsSkipped) {
  constexpr int kTests = 60;
  WriteCsvTests(dir_ / "k", kTests);
  for (int round = 0; round < 3; ++round) {
    const std::string db = "two-imports-" + std::to_string(round) + ".db";
    if (round == 2) {
      ASSERT_EQ(Napkin({"--db", db, "init"}).exit_code, 0);  // an existing catalogue too
    }
    const std::vector<std::string> args = {"--db", db, "--quiet", "import", "--array", "denton-3222", "k"};
    const pid_t a = Start(args, "a");
    const pid_t b = Start(args, "b");
    const CommandResult first = Finished(a, "a");
    const CommandResult second = Finished(b, "b");
    int imported = 0;
    for (const CommandResult* import : {&first, &second}) {
      EXPECT_EQ(import->exit_code, 0) << "round " << round << ":\n" << import->err;
      EXPECT_EQ(import->err, "") << "round " << round;
      const auto [stored, skipped] = ImportCounts(*import);
      EXPECT_EQ(stored + skipped, kTests) << import->out;
      imported += stored;
    }
    EXPECT_EQ(imported, kTests) << "each test stored by exactly one of the two";
    ExpectSound(dir_ / db, "round " + std::to_string(round));
    EXPECT_EQ(CountRowsOrZero(dir_ / db, "tests"), kTests);
  }
}

TEST_F(Faults, TwoRunsAtOnceProcessEachTestOnce) {
  Synth("runs.db", 40, 500);
  const pid_t a = Start({"--db", "runs.db", "--quiet", "run", "--threads", "1"}, "a");
  const pid_t b = Start({"--db", "runs.db", "--quiet", "run", "--threads", "1"}, "b");
  const CommandResult first = Finished(a, "a");
  const CommandResult second = Finished(b, "b");
  EXPECT_EQ(first.exit_code, 0) << first.err;
  EXPECT_EQ(second.exit_code, 0) << second.err;
  ExpectSound(dir_ / "runs.db", "after two runs");
  db::Catalogue catalogue = test_support::OpenForReading(dir_ / "runs.db");
  db::CatalogueInspector inspector(catalogue);
  EXPECT_EQ(inspector.CountRows("results"), 40);
  EXPECT_EQ(inspector.CountDoneJobsClaimedOnce(), 40);
}

// ------------------------------------------------------------------ SIGKILL

TEST_F(Faults, ImportKilledThenResumedStoresEveryTestOnceAndWhole) {
  constexpr int kTests = 150;
  WriteCsvTests(dir_ / "k", kTests);
  const std::vector<std::string> args = {"--db",    "kill.db",     "--quiet", "import",
                                         "--array", "denton-3222", "k"};
  ASSERT_TRUE(KillAfterRows(Start(args, "killed"), dir_ / "kill.db", "tests", 10))
      << "the import ended before the kill";
  ExpectSound(dir_ / "kill.db", "after the kill");
  const std::int64_t kept = CountRowsOrZero(dir_ / "kill.db", "tests");
  EXPECT_GE(kept, 10);
  const CommandResult rerun = Napkin(args);
  EXPECT_EQ(rerun.exit_code, 0) << rerun.err;
  EXPECT_EQ(ImportCounts(rerun), std::make_pair(kTests - static_cast<int>(kept), static_cast<int>(kept)));
  ExpectSound(dir_ / "kill.db", "after the rerun");
  EXPECT_EQ(CountRowsOrZero(dir_ / "kill.db", "tests"), kTests);
}

TEST_F(Faults, RunKilledThenResumedCompletesEveryTestOnce) {
  Synth("kill.db", 100, 2000);
  ASSERT_TRUE(KillAfterRows(Start({"--db", "kill.db", "--quiet", "run", "--threads", "2"}, "killed"),
                            dir_ / "kill.db", "results", 8))
      << "the run ended before the kill";
  ExpectSound(dir_ / "kill.db", "after the kill");
  EXPECT_LT(CountRowsOrZero(dir_ / "kill.db", "results"), 100);
  const CommandResult rerun = Napkin({"--db", "kill.db", "--quiet", "run", "--threads", "2"});
  EXPECT_EQ(rerun.exit_code, 0) << rerun.err;
  ExpectSound(dir_ / "kill.db", "after the rerun");
  EXPECT_EQ(CountRowsOrZero(dir_ / "kill.db", "results"), 100);
}

// ---------------------------------------------------------- full filesystem

// Runs `napkin args` on a copy of `seed` (when given) as `full.db` on a tmpfs
// of `kib` KiB mounted in a private mount namespace (unshare -m: the mount
// vanishes with the process), then copies the catalogue (and its journal)
// back to dir_/full/. False (with the reason in `why`) where mounting is not
// allowed.
bool RunOnSmallFilesystem(const fs::path& dir, const std::string& seed, int kib,
                          const std::vector<std::string>& args, CommandResult& result, std::string& why) {
  if (geteuid() != 0 || !fs::exists("/usr/bin/unshare")) {
    why = "mounting a size-limited tmpfs needs root and unshare(1)";
    return false;
  }
  fs::create_directories(dir / "mnt");
  fs::create_directories(dir / "full");
  std::string command = "mount -t tmpfs -o size=" + std::to_string(kib) + "k tmpfs mnt || exit 99; ";
  if (!seed.empty()) command += "cp '" + seed + "' mnt/full.db || exit 98; ";
  command += "'" + NapkinBinary() + "' --db mnt/full.db --quiet";
  for (const std::string& arg : args) command += " '" + arg + "'";
  command += " > full.out 2> full.err; status=$?; cp mnt/full.db* full/; exit $status";
  result = test_support::RunProgram("/usr/bin/unshare", {"-m", "/bin/sh", "-c", command}, dir);
  if (result.exit_code == 99) {
    why = "mounting a tmpfs is not allowed here";
    return false;
  }
  result.out = ReadText(dir / "full.out");
  result.err = ReadText(dir / "full.err");
  return true;
}

TEST_F(Faults, FullFilesystemDuringImportAndRunEndsWithOneSentenceAndASoundCatalogue) {
  // Import (synth: the same store path) until the disk is full.
  CommandResult synth;
  std::string why;
  if (!RunOnSmallFilesystem(dir_.path(), "", 1024,
                            {"synth", "--scenario", "random", "--count", "40", "--samples", "2000"}, synth,
                            why))
    GTEST_SKIP() << why;
  EXPECT_EQ(synth.exit_code, 1) << synth.out;
  ExpectOneSentenceError(synth, {"catalogue 'mnt/full.db'", "disk", "full", "free space"});
  EXPECT_EQ(synth.err.find(".cpp"), std::string::npos) << synth.err;
  EXPECT_EQ(synth.err.find("SQLite"), std::string::npos) << synth.err;
  ExpectSound(dir_ / "full" / "full.db", "after the full disk during import");
  const std::int64_t stored = CountRowsOrZero(dir_ / "full" / "full.db", "tests");
  EXPECT_GT(stored, 0);
  EXPECT_LT(stored, 40);

  // Run: the tests fit, their results do not.
  Synth("seed.db", 4, 2000);
  CommandResult run;
  ASSERT_TRUE(RunOnSmallFilesystem(dir_.path(), (dir_ / "seed.db").string(),
                                   static_cast<int>(fs::file_size(dir_ / "seed.db") / 1024) + 700,
                                   {"run", "--threads", "1"}, run, why))
      << why;
  EXPECT_EQ(run.exit_code, 1) << run.out;
  // The run's time-stamped information line aside, one error sentence.
  CommandResult errors = run;
  errors.err.clear();
  for (const std::string& line : Lines(run.err))
    if (line.rfind("napkin: ", 0) == 0) errors.err += line + "\n";
  ExpectOneSentenceError(errors, {"catalogue 'mnt/full.db'", "disk", "full", "free space"});
  EXPECT_EQ(run.err.find(".cpp"), std::string::npos) << run.err;
  ExpectSound(dir_ / "full" / "full.db", "after the full disk during run");
  EXPECT_LT(CountRowsOrZero(dir_ / "full" / "full.db", "results"), 4);
  // With room again the run completes.
  const CommandResult rerun = Napkin({"--db", "full/full.db", "--quiet", "run"});
  EXPECT_EQ(rerun.exit_code, 0) << rerun.err;
  ExpectSound(dir_ / "full" / "full.db", "after the rerun");
  EXPECT_EQ(CountRowsOrZero(dir_ / "full" / "full.db", "results"), 4);
}

// ---------------------------------------------------------------- read-only

TEST_F(Faults, ReadOnlyFileAnswersQueriesAndRefusesWritesInOneSentence) {
  Synth("ro.db", 3, 500);
  ASSERT_EQ(Napkin({"--db", "ro.db", "--quiet", "run"}).exit_code, 0);
  fs::permissions(dir_ / "ro.db", fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  const std::string before = ReadText(dir_ / "ro.db");
  const CommandResult query = Napkin({"--db", "ro.db", "query", "tests", "--format", "csv"});
  EXPECT_EQ(query.exit_code, 0) << query.err;
  EXPECT_EQ(Lines(query.out).size(), 4u);
  const CommandResult status = Napkin({"--db", "ro.db", "status", "--format", "json"});
  EXPECT_EQ(status.exit_code, 0) << status.err;
  for (const std::vector<std::string>& command :
       {std::vector<std::string>{"init"}, std::vector<std::string>{"run"},
        std::vector<std::string>{"synth", "--scenario", "random", "--seed", "99"}}) {
    const CommandResult refused = Napkin(Concat({"--db", "ro.db"}, command));
    EXPECT_EQ(refused.exit_code, 1) << command.front();
    ExpectOneSentenceError(refused, {"ro.db", "read-only"});
  }
  EXPECT_EQ(ReadText(dir_ / "ro.db"), before);
  ExpectSound(dir_ / "ro.db", "read-only file");
}

// Issue 11 item 6: a writable catalogue in a directory its user may not
// write. query and status work; writing commands fail with one sentence
// naming the catalogue and the directory and what to do.
TEST_F(Faults, ReadOnlyDirectoryAnswersQueriesAndRefusesWritesInOneSentence) {
  const passwd* nobody = getpwnam("nobody");
  const bool root = geteuid() == 0;
  if (root && (nobody == nullptr || !fs::exists("/usr/bin/setpriv")))
    GTEST_SKIP() << "running as root without user nobody or setpriv(1): the directory cannot be made "
                    "read-only for napkin";
  fs::create_directories(dir_ / "locked");
  Synth("locked/c.db", 3, 500);
  ASSERT_EQ(Napkin({"--db", "locked/c.db", "--quiet", "run"}).exit_code, 0);
  if (root) {
    ASSERT_EQ(chown((dir_ / "locked" / "c.db").c_str(), nobody->pw_uid, nobody->pw_gid), 0);
  }
  fs::permissions(dir_.path(), fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                                   fs::perms::others_read | fs::perms::others_exec);
  fs::permissions(dir_ / "locked", fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read |
                                       fs::perms::group_exec | fs::perms::others_read |
                                       fs::perms::others_exec);
  const std::string before = ReadText(dir_ / "locked" / "c.db");
  auto run = [&](const std::vector<std::string>& args) {
    const std::vector<std::string> napkin = Concat({"--db", "locked/c.db"}, args);
    if (!root) return Napkin(napkin);
    return test_support::RunProgram(
        "/usr/bin/setpriv",
        Concat({"--reuid=" + std::to_string(nobody->pw_uid), "--regid=" + std::to_string(nobody->pw_gid),
                "--clear-groups", NapkinBinary()},
               napkin),
        dir_.path());
  };

  const CommandResult query = run({"query", "hic", "--format", "csv"});
  EXPECT_EQ(query.exit_code, 0) << query.err;
  EXPECT_EQ(Lines(query.out).size(), 4u) << query.out;
  const CommandResult status = run({"status", "--format", "json"});
  EXPECT_EQ(status.exit_code, 0) << status.err;
  EXPECT_NE(status.out.find("\"done\": 3"), std::string::npos) << status.out;
  WriteCsvTests(dir_ / "k", 1);
  for (const std::vector<std::string>& command :
       {std::vector<std::string>{"init"}, std::vector<std::string>{"run", "--force"},
        std::vector<std::string>{"import", "--array", "denton-3222", "k"}}) {
    const CommandResult refused = run(command);
    EXPECT_EQ(refused.exit_code, 1) << command.front();
    ExpectOneSentenceError(refused, {"catalogue 'locked/c.db'", "directory 'locked'", "read-only",
                                     "make the directory writable"});
    EXPECT_EQ(refused.err.find(".cpp"), std::string::npos) << refused.err;
  }
  fs::permissions(dir_ / "locked", fs::perms::owner_all);
  EXPECT_EQ(ReadText(dir_ / "locked" / "c.db"), before);
  ExpectSound(dir_ / "locked" / "c.db", "read-only directory");
}

// ---------------------------------------------------------------- corruption

// Issue 11 item 10: a damaged page is named as damage of the catalogue with
// what to do (no SQLite text, no source path); init does not call it up to
// date, and import writes nothing into it.
TEST_F(Faults, CorruptedPageIsReportedAndNeverWrittenInto) {
  Synth("bad.db", 20, 500);
  std::int64_t page_size = 0;
  std::int64_t tests_root = 0;
  {
    db::Catalogue catalogue = test_support::OpenForReading(dir_ / "bad.db");
    db::CatalogueInspector inspector(catalogue);
    page_size = Scalar(inspector, "PRAGMA page_size");
    tests_root = Scalar(inspector, "SELECT rootpage FROM sqlite_master WHERE name = 'tests'");
  }
  ASSERT_TRUE(!fs::exists(dir_ / "bad.db-wal") || fs::file_size(dir_ / "bad.db-wal") == 0)
      << "the journal was checkpointed into the file";
  {
    // Overwrite the first 64 bytes of the tests table's root page (its b-tree header).
    std::fstream file(dir_ / "bad.db", std::ios::in | std::ios::out | std::ios::binary);
    file.seekp((tests_root - 1) * page_size);
    const std::string garbage(64, '\xA5');
    file.write(garbage.data(), static_cast<std::streamsize>(garbage.size()));
  }
  const std::string damaged = ReadText(dir_ / "bad.db");
  WriteCsvTests(dir_ / "k", 2);
  for (const std::vector<std::string>& command :
       {std::vector<std::string>{"init"}, std::vector<std::string>{"import", "--array", "denton-3222", "k"},
        std::vector<std::string>{"run"}, std::vector<std::string>{"query", "tests"}}) {
    const CommandResult refused = Napkin(Concat({"--db", "bad.db"}, command));
    EXPECT_EQ(refused.exit_code, 1) << command.front() << ": " << refused.out;
    EXPECT_EQ(refused.out.find("up to date"), std::string::npos) << refused.out;
    ExpectOneSentenceError(refused, {"catalogue 'bad.db'", "damaged", "backup", ".recover"});
    EXPECT_EQ(refused.err.find(".cpp"), std::string::npos) << refused.err;
    EXPECT_EQ(refused.err.find("malformed'"), std::string::npos) << refused.err;
    EXPECT_EQ(ReadText(dir_ / "bad.db"), damaged) << command.front() << " wrote into the damaged file";
  }
}

TEST_F(Faults, FileThatIsNotSqliteIsRefusedAndUntouched) {
  const std::string text = "test_id,hic15\nv1,700\n";
  test_support::WriteText(dir_ / "notes.db", text);
  WriteCsvTests(dir_ / "k", 1);
  for (const std::vector<std::string>& command :
       {std::vector<std::string>{"init"}, std::vector<std::string>{"import", "--array", "denton-3222", "k"},
        std::vector<std::string>{"query", "tests"}, std::vector<std::string>{"status"}}) {
    const CommandResult refused = Napkin(Concat({"--db", "notes.db"}, command));
    EXPECT_EQ(refused.exit_code, 1) << command.front();
    ExpectOneSentenceError(refused, {"'notes.db' is not a napkin catalogue"});
  }
  EXPECT_EQ(ReadText(dir_ / "notes.db"), text);
}

// ------------------------------------------------------------ merge guard

// Issue 11 item 7: merging the catalogue into itself is refused at once under
// every name of its file (the device and inode are compared, not names).
TEST_F(Faults, MergeOfTheCatalogueIntoItselfIsRefusedAtOnceUnderEverySpelling) {
  Synth("m.db", 3, 500);
  ASSERT_EQ(Napkin({"--db", "m.db", "--quiet", "run"}).exit_code, 0);
  fs::create_directories(dir_ / "sub");
  fs::create_symlink("m.db", dir_ / "link.db");
  fs::create_hard_link(dir_ / "m.db", dir_ / "hard.db");
  const std::string absolute = (dir_ / "m.db").string();
  const std::string before = test_support::DumpCatalogue(dir_ / "m.db");
  for (const std::string& spelling :
       {std::string("m.db"), std::string("./m.db"), std::string("sub/../m.db"), absolute,
        std::string("link.db"), std::string("hard.db"), std::string("file:m.db"), std::string("file:./m.db"),
        "file:" + absolute, "file://" + absolute, std::string("file:m.db?mode=ro"),
        std::string("file:link.db?cache=private"), std::string("file:hard.db")}) {
    const auto start = std::chrono::steady_clock::now();
    const CommandResult merge = Napkin({"--db", "m.db", "merge", spelling});
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(merge.exit_code, 1) << spelling;
    ExpectOneSentenceError(merge, {"shard '" + spelling + "'", "is the catalogue 'm.db' itself"});
    EXPECT_LT(seconds, 10.0) << spelling << ": refused at once, not after the lock wait";
  }
  EXPECT_EQ(test_support::DumpCatalogue(dir_ / "m.db"), before);
  ExpectSound(dir_ / "m.db", "after the refused merges");
}

}  // namespace
}  // namespace napkin
