// What `--db` and `run --results` may name (issue 29 points 7 and 12;
// docs/formats.md "The catalogue file", db/README.md): a regular file or a
// name not yet taken; a named pipe, a device or a folder is refused in one
// sentence naming it, at once (a FIFO never blocks the open) and without a
// file appearing beside it. Read commands leave the catalogue's folder as
// they found it: no -wal or -shm file stays behind, and those of a process
// that still has the catalogue open are left to it.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "db/catalogue.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"

namespace napkin {
namespace {

namespace fs = std::filesystem;
using test_support::ExpectOneSentenceError;
using test_support::ReadText;
using test_support::RunNapkin;
using test_support::RunResult;

std::vector<std::string> FilesIn(const fs::path& directory) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(directory)) names.push_back(entry.path().filename());
  std::sort(names.begin(), names.end());
  return names;
}

class CatalogueFiles : public ::testing::Test {
 protected:
  // Runs napkin in dir_, killing it after `seconds` (a blocked open): the
  // result's exit_code is then -2.
  RunResult NapkinWithin(const std::vector<std::string>& args, int seconds = 30) {
    const pid_t pid = test_support::StartProgram(NAPKIN_BINARY, args, logs_ / "stdout.txt",
                                                 logs_ / "stderr.txt", dir_.path());
    RunResult result;
    int status = 0;
    bool exited = false;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
    while (!(exited = ::waitpid(pid, &status, WNOHANG) == pid) && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (!exited) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      result.exit_code = -2;
    } else {
      result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    result.out = ReadText(logs_ / "stdout.txt");
    result.err = ReadText(logs_ / "stderr.txt");
    return result;
  }

  napkin::test_support::TempDir dir_;
  napkin::test_support::TempDir logs_;  // napkin's stdout and stderr
};

// `mkfifo f; napkin --db f query tests` blocked for ever in open(2).
TEST_F(CatalogueFiles, ANamedPipeIsRefusedAtOnce) {
  const fs::path fifo = dir_ / "f";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const std::vector<std::string>& command :
       {std::vector<std::string>{"query", "tests"}, std::vector<std::string>{"init"},
        std::vector<std::string>{"status"}}) {
    std::vector<std::string> args = {"--db", "f"};
    args.insert(args.end(), command.begin(), command.end());
    const RunResult run = NapkinWithin(args);
    ASSERT_NE(run.exit_code, -2) << "napkin " << command.front() << " blocked on the FIFO";
    EXPECT_EQ(run.exit_code, 1) << run.err;
    ExpectOneSentenceError(run, {"catalogue 'f' is a named pipe (FIFO), not a file"});
    EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo)));
  }
  EXPECT_EQ(FilesIn(dir_.path()), std::vector<std::string>{"f"});
}

// `--db /dev/null init` said "SQLite error 'disk I/O error'" and left a
// world-writable /dev/null-journal. Checked on a private device node
// (needs root) and on /dev/null itself.
TEST_F(CatalogueFiles, ADeviceIsRefusedAndNothingIsCreatedBesideIt) {
  const bool journal_before = fs::exists("/dev/null-journal");
  for (const std::vector<std::string>& command :
       {std::vector<std::string>{"init"}, std::vector<std::string>{"query", "tests"}}) {
    std::vector<std::string> args = {"--db", "/dev/null"};
    args.insert(args.end(), command.begin(), command.end());
    const RunResult run = NapkinWithin(args);
    EXPECT_EQ(run.exit_code, 1) << run.err;
    ExpectOneSentenceError(run, {"catalogue '/dev/null' is a character device, not a file"});
  }
  EXPECT_TRUE(fs::is_character_file(fs::symlink_status("/dev/null")));
  if (!journal_before) {
    EXPECT_FALSE(fs::exists("/dev/null-journal"));
    if (fs::is_regular_file(fs::symlink_status("/dev/null-journal"))) fs::remove("/dev/null-journal");
  }

  const fs::path node = dir_ / "null";
  if (::mknod(node.c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0)
    GTEST_SKIP() << "cannot make a device node (needs root): " << std::strerror(errno);
  for (const char* command : {"init", "import"}) {
    std::vector<std::string> args = {"--db", "null", command};
    if (std::string(command) == "import")
      args.insert(args.end(), {"--array", "denton-3222", dir_.path().string()});
    const RunResult run = NapkinWithin(args);
    EXPECT_EQ(run.exit_code, 1) << run.err;
    ExpectOneSentenceError(run, {"catalogue 'null' is a character device, not a file"});
    EXPECT_EQ(FilesIn(dir_.path()), std::vector<std::string>{"null"});
  }
}

// `--db <folder>` said "disk I/O error".
TEST_F(CatalogueFiles, AFolderIsRefused) {
  fs::create_directory(dir_ / "folder");
  for (const std::vector<std::string>& command :
       {std::vector<std::string>{"init"}, std::vector<std::string>{"query", "tests"}}) {
    std::vector<std::string> args = {"--db", "folder"};
    args.insert(args.end(), command.begin(), command.end());
    const RunResult run = NapkinWithin(args);
    EXPECT_EQ(run.exit_code, 1) << run.err;
    ExpectOneSentenceError(run, {"catalogue 'folder' is a directory, not a file"});
  }
  EXPECT_EQ(FilesIn(dir_ / "folder"), std::vector<std::string>{});
}

// `run --results /dev/null` blamed lab.db; a FIFO results file blocked.
TEST_F(CatalogueFiles, AResultsFileThatIsNoFileIsRefusedNamingIt) {
  ASSERT_EQ(RunNapkin(dir_.path(),
                      {"--db", "lab.db", "synth", "--scenario", "random", "--count", "2", "--samples", "500"})
                .exit_code,
            0);
  ASSERT_EQ(::mkfifo((dir_ / "pipe.db").c_str(), 0600), 0);
  const bool journal_before = fs::exists("/dev/null-journal");
  for (const auto& [results, kind] : {std::pair<std::string, std::string>{"/dev/null", "a character device"},
                                      {"pipe.db", "a named pipe (FIFO)"}}) {
    const RunResult run = NapkinWithin({"--db", "lab.db", "run", "--shard", "0/1", "--results", results});
    ASSERT_NE(run.exit_code, -2) << "run --results " << results << " blocked";
    EXPECT_EQ(run.exit_code, 1) << run.err;
    ExpectOneSentenceError(run, {"results file '" + results + "' is " + kind + ", not a file"});
    EXPECT_EQ(run.err.find("lab.db"), std::string::npos) << run.err;
  }
  EXPECT_EQ(FilesIn(dir_.path()), (std::vector<std::string>{"lab.db", "pipe.db"}));
  if (!journal_before) {
    EXPECT_FALSE(fs::exists("/dev/null-journal"));
    if (fs::is_regular_file(fs::symlink_status("/dev/null-journal"))) fs::remove("/dev/null-journal");
  }
}

// Read commands and a refused merge left -wal and -shm files beside the
// catalogue (a read-only SQLite connection cannot remove them on close).
class ReadCommandsLeaveTheFolder : public CatalogueFiles {
 protected:
  void SetUp() override {
    fs::create_directory(lab_);
    ASSERT_EQ(Napkin({"synth", "--scenario", "padding-series", "--count", "2"}).exit_code, 0);
    const RunResult run = Napkin({"run"});
    ASSERT_EQ(run.exit_code, 0) << run.err;
    ASSERT_EQ(FilesIn(lab_), std::vector<std::string>{"lab.db"});
  }

  RunResult Napkin(std::vector<std::string> args) {
    args.insert(args.begin(), {"--db", (lab_ / "lab.db").string()});
    return RunNapkin(dir_.path(), args);
  }

  std::vector<std::vector<std::string>> ReadCommands() const {
    const std::string out = (dir_ / "out").string();
    return {{"query", "tests"},
            {"query", "hic"},
            {"status"},
            {"compare", "--series", "padding-series"},
            {"export", "--test", test_id_, "--format", "csv", "--out", out + ".csv"},
            {"report", "--out", out + ".html"}};
  }

  fs::path lab_ = dir_ / "lab";
  std::string test_id_ = "padding-series-foam-a-01";
};

TEST_F(ReadCommandsLeaveTheFolder, NoLogOrIndexStaysBehind) {
  const std::string before = ReadText(lab_ / "lab.db");
  for (const std::vector<std::string>& command : ReadCommands()) {
    const RunResult run = Napkin(command);
    EXPECT_EQ(run.exit_code, 0) << command.front() << ": " << run.err;
    EXPECT_EQ(FilesIn(lab_), std::vector<std::string>{"lab.db"}) << "after " << command.front();
  }
  EXPECT_TRUE(ReadText(lab_ / "lab.db") == before) << "a read command changed the catalogue";
}

// Another process's log and index are its own: a read command beside it
// leaves them (and the data written through them) in place.
TEST_F(ReadCommandsLeaveTheFolder, TheFilesOfAnotherProcessAreLeftToIt) {
  db::Catalogue writer = db::Catalogue::Open((lab_ / "lab.db").string());
  writer.WriteSeries("written-by-the-other", "");
  ASSERT_TRUE(fs::exists(lab_ / "lab.db-wal"));
  for (const std::vector<std::string>& command : ReadCommands()) {
    const RunResult run = Napkin(command);
    EXPECT_EQ(run.exit_code, 0) << command.front() << ": " << run.err;
    EXPECT_EQ(FilesIn(lab_), (std::vector<std::string>{"lab.db", "lab.db-shm", "lab.db-wal"}))
        << "after " << command.front();
  }
  EXPECT_TRUE(writer.ReadSeries("written-by-the-other").has_value());
}

// A refused merge of a hard link to the catalogue left H.db-wal.
TEST_F(ReadCommandsLeaveTheFolder, ARefusedMergeOfAHardLinkLeavesNothing) {
  fs::create_hard_link(lab_ / "lab.db", lab_ / "H.db");
  const RunResult merge = Napkin({"merge", (lab_ / "H.db").string()});
  EXPECT_EQ(merge.exit_code, 1) << merge.err;
  ExpectOneSentenceError(merge, {"is the catalogue", "itself"});
  EXPECT_EQ(FilesIn(lab_), (std::vector<std::string>{"H.db", "lab.db"}));
}

}  // namespace
}  // namespace napkin
