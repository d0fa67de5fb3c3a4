// Issue 19 items 1-3: no output of napkin destroys data. A folder export
// (ISO-MME, UDS) writes its files beside what the folder holds and refuses a
// taken name unless --force; the demo writes only into a new, empty or
// earlier demo folder; no command writes over the catalogue or its side files
// by any spelling (symbolic link, hard link, "./", "a/.."); a symbolic link
// is written through, a FIFO or character device is written straight into,
// and "--out -" is standard output (docs/formats.md "Output destinations").
// Data-loss checks compare a listing with content hashes of the folder and a
// catalogue dump before and after.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "formats/csv.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"
#include "util/sha256.h"

namespace napkin::cli {

using namespace napkin::test_support;
namespace {

// Every entry under `dir` (relative path) with what it is: a folder, a
// symbolic link and its target, a FIFO, a device, or a file's SHA-256.
// The catalogue's transient SQLite side files are left out (a reader may
// leave them); the catalogue itself is compared by hash and dump.
std::map<std::string, std::string> Listing(const fs::path& dir) {
  std::map<std::string, std::string> listing;
  for (auto entry = fs::recursive_directory_iterator(dir); entry != fs::recursive_directory_iterator();
       ++entry) {
    const std::string name = entry->path().lexically_relative(dir).generic_string();
    if (name.ends_with("-shm") || name.ends_with("-wal")) continue;
    const fs::file_status status = entry->symlink_status();
    if (fs::is_symlink(status))
      listing[name] = "link:" + fs::read_symlink(entry->path()).string();
    else if (fs::is_directory(status))
      listing[name] = "folder";
    else if (fs::is_fifo(status))
      listing[name] = "fifo";
    else if (fs::is_character_file(status))
      listing[name] = "character device";
    else
      listing[name] = util::Sha256Hex(ReadText(entry->path()));
  }
  return listing;
}

std::vector<std::string> Added(const std::map<std::string, std::string>& before,
                               const std::map<std::string, std::string>& after) {
  std::vector<std::string> added;
  for (const auto& [name, what] : after)
    if (!before.count(name)) added.push_back(name);
  return added;
}

class OutputDestinations : public ::testing::Test {
 protected:
  // lab/lab.db holds tests e1 and e2 with results; lab/important/thesis.txt
  // is the user's.
  void SetUp() override {
    lab_ = dir_ / "lab";
    fs::create_directories(lab_ / "important");
    WriteText(lab_ / "important" / "thesis.txt", "chapter 1\n");
    for (const char* id : {"e1", "e2"}) {
      const synth::SyntheticTest synth = SynthNapTest(id[1] == '1' ? 11 : 12, 0.03);
      formats::WriteSignalsCsv(synth.signals, dir_ / (std::string(id) + ".csv"));
    }
    const RunResult import = RunNapkin(dir_.path(), {"--db", Db(), "import", "--array", "denton-3222",
                                                     "--series", "sled", "e1.csv", "e2.csv"});
    ASSERT_EQ(import.exit_code, 0) << import.err;
    ProcessAndStore(Db(), "e1");
    ProcessAndStore(Db(), "e2");
  }

  std::string Db() const { return (lab_ / "lab.db").string(); }

  RunResult Napkin(std::vector<std::string> args) {
    args.insert(args.begin(), {"--db", Db()});
    return RunNapkin(dir_.path(), args);
  }

  // The CSV export of e1 to a fresh file: what every destination must receive.
  std::string ReferenceCsv() {
    const RunResult exported =
        Napkin({"export", "--test", "e1", "--format", "csv", "--out", "reference.csv"});
    EXPECT_EQ(exported.exit_code, 0) << exported.err;
    return ReadText(dir_ / "reference.csv");
  }

  TempDir dir_;
  fs::path lab_;
};

// Item 1: the folder held the catalogue and the user's thesis; the export
// used to empty it. Now both stay, byte for byte, a second test's export
// keeps the first's files, and a taken name is refused unless --force.
TEST_F(OutputDestinations, FolderExportsWriteBesideWhatTheFolderHolds) {
  for (const std::string format : {"isomme", "uds"}) {
    SCOPED_TRACE(format);
    const std::string dump = DumpCatalogue(Db());
    const std::map<std::string, std::string> before = Listing(lab_);
    ASSERT_TRUE(before.count("lab.db"));

    const RunResult first = Napkin({"export", "--test", "e1", "--format", format, "--out", lab_.string()});
    ASSERT_EQ(first.exit_code, 0) << first.err;
    const std::map<std::string, std::string> after_first = Listing(lab_);
    for (const auto& [name, what] : before) {
      ASSERT_TRUE(after_first.count(name)) << name << " was removed";
      EXPECT_EQ(after_first.at(name), what) << name << " was changed";
    }
    const std::vector<std::string> e1_files = Added(before, after_first);
    EXPECT_GE(e1_files.size(), format == "isomme" ? 20u : 21u);
    for (const std::string& name : e1_files) {
      EXPECT_EQ(name.find(".napkin-staging"), std::string::npos) << name;
      EXPECT_TRUE(name == "Channel" || name.find("e1") != std::string::npos) << name;
    }

    // A second test into the same folder: both tests' files.
    const RunResult second = Napkin({"export", "--test", "e2", "--format", format, "--out", lab_.string()});
    ASSERT_EQ(second.exit_code, 0) << second.err;
    const std::map<std::string, std::string> after_second = Listing(lab_);
    for (const auto& [name, what] : after_first) EXPECT_EQ(after_second.at(name), what) << name;
    EXPECT_EQ(Added(after_first, after_second).size(),
              e1_files.size() - (format == "isomme" ? 1u : 0u));  // the Channel folder is shared

    // The same test again: refused in one sentence naming a taken file, nothing changed.
    const RunResult again = Napkin({"export", "--test", "e1", "--format", format, "--out", lab_.string()});
    EXPECT_EQ(again.exit_code, 1);
    ExpectOneSentenceError(again, {"already exists", "unless --force is given"});
    EXPECT_EQ(Listing(lab_), after_second);
    // --force replaces the export's own names only.
    const RunResult forced =
        Napkin({"export", "--test", "e1", "--format", format, "--out", lab_.string(), "--force"});
    ASSERT_EQ(forced.exit_code, 0) << forced.err;
    EXPECT_EQ(Listing(lab_), after_second);  // the same bytes under the same names
    EXPECT_EQ(DumpCatalogue(Db()), dump);

    // Clean up the exported files for the next format (the test's own files).
    for (const std::string& name : Added(before, after_second)) fs::remove_all(lab_ / name);
    ASSERT_EQ(Listing(lab_), before);
  }
}

// Item 1: `demo --out .` in a lab folder deleted the user's napkin.db and csv/.
TEST_F(OutputDestinations, DemoRefusesAFolderWithTheUsersFiles) {
  const fs::path folder = dir_ / "mylab";
  fs::create_directories(folder / "csv");
  WriteText(folder / "csv" / "mydata.csv", "time_s,a\n0,1\n");
  fs::copy_file(Db(), folder / "napkin.db");
  const std::string dump = DumpCatalogue(folder / "napkin.db");
  const std::map<std::string, std::string> before = Listing(folder);
  const RunResult demo = RunNapkin(folder, {"demo", "--out", "."});
  EXPECT_EQ(demo.exit_code, 1);
  ExpectOneSentenceError(demo, {"which no earlier demo's stamp (.napkin-demo) lists"});
  EXPECT_EQ(Listing(folder), before);
  EXPECT_EQ(DumpCatalogue(folder / "napkin.db"), dump);

  // A stamped demo folder with one file the demo did not write is refused too.
  const fs::path stamped = dir_ / "old-demo";
  fs::create_directories(stamped);
  WriteText(stamped / ".napkin-demo", "# napkin demo\nreport.html\n../outside.txt\n");
  WriteText(stamped / "report.html", "<html></html>\n");
  WriteText(stamped / "notes.txt", "mine\n");
  WriteText(dir_ / "outside.txt", "mine too\n");
  const std::map<std::string, std::string> stamped_before = Listing(dir_.path());
  const RunResult again = RunNapkin(dir_.path(), {"demo", "--out", "old-demo"});
  EXPECT_EQ(again.exit_code, 1);
  ExpectOneSentenceError(again, {"notes.txt", "which no earlier demo's stamp (.napkin-demo) lists"});
  EXPECT_EQ(Listing(dir_.path()), stamped_before);
}

// Item 2: every command that writes a file refuses the catalogue and its
// side files, under every spelling; the catalogue stays byte for byte.
TEST_F(OutputDestinations, NoOutputReplacesTheCatalogue) {
  fs::create_directories(dir_ / "sub");
  fs::create_symlink("lab/lab.db", dir_ / "link.db");
  fs::create_hard_link(lab_ / "lab.db", dir_ / "hard.db");
  fs::create_symlink("lab/lab.db-wal", dir_ / "wal-link");  // dangling: no log while nothing is open
  const std::string db = "lab/lab.db";
  const std::string dump = DumpCatalogue(Db());
  const std::map<std::string, std::string> before = Listing(dir_.path());

  auto refused = [&](const std::vector<std::string>& args, const std::string& fragment) {
    std::vector<std::string> full = {"--db", db};
    full.insert(full.end(), args.begin(), args.end());
    const RunResult run = RunNapkin(dir_.path(), full);
    EXPECT_EQ(run.exit_code, 1) << ::testing::PrintToString(args) << run.err;
    ExpectOneSentenceError(run, {fragment, "napkin never writes output over it"});
    EXPECT_EQ(Listing(dir_.path()), before) << ::testing::PrintToString(args);
    EXPECT_FALSE(fs::exists(fs::symlink_status(lab_ / "lab.db-wal")) &&
                 fs::file_size(lab_ / "lab.db-wal") > 0)
        << ::testing::PrintToString(args);
  };
  const std::string itself = "the catalogue 'lab/lab.db' itself";
  for (const std::string spelling : {"lab/lab.db", "./lab/lab.db", "sub/../lab/lab.db", "link.db", "hard.db"})
    refused({"export", "--test", "e1", "--format", "csv", "--out", spelling}, itself);
  refused({"export", "--test", "e1", "--format", "csv", "--out", "lab/lab.db-wal"}, "write-ahead log");
  refused({"export", "--test", "e1", "--format", "csv", "--out", "wal-link"}, "write-ahead log");
  refused({"export", "--test", "e1", "--format", "csv", "--out", "lab/lab.db-shm"}, "shared-memory index");
  refused({"export", "--test", "e1", "--format", "lsdyna", "--out", "./lab/lab.db"}, itself);
  refused({"export", "--test", "e1", "--format", "lcfile", "--out", "link.db"}, itself);
  refused({"report", "--out", "hard.db"}, itself);
  refused({"report", "--out", "./lab/lab.db"}, itself);
  refused({"transform", "--array", "denton-3222", "e1.csv", "--out", "link.db"}, itself);
  refused({"transform", "--array", "denton-3222", "e1.csv", "--out", "t.csv", "--summary", "hard.db"},
          itself);
  refused({"transform", "--array", "denton-3222", "e1.csv", "--out", "t.csv", "--lsdyna", "lab/lab.db"},
          itself);
  refused({"run", "--results", "lab/lab.db-wal"}, "write-ahead log");
  refused({"run", "--results", "link.db"}, itself);
  EXPECT_EQ(DumpCatalogue(Db()), dump);
  // The README says the exit status each refusal has: 1 for the catalogue, 2 for a command's own
  // inputs and outputs (issue 42, point 17: it said 2 for all of them).
  const std::string readme = ReadText(fs::path(NAPKIN_SOURCE_DIR) / "README.md");
  EXPECT_NE(readme.find("(link, hard link, `./`; exit 1, as for\nother input napkin refuses)"),
            std::string::npos);
  EXPECT_NE(readme.find("another of its outputs (exit 2: the\ncommand line names one file twice)"),
            std::string::npos);
}

// Item 3: a symbolic link is written through to its target (existing or
// not); the link stays, and no temporary file is left beside either.
TEST_F(OutputDestinations, OutputThroughASymbolicLinkWritesItsTarget) {
  const std::string reference = ReferenceCsv();
  fs::create_directories(dir_ / "here");
  fs::create_directories(dir_ / "elsewhere");
  WriteText(dir_ / "elsewhere" / "target.csv", "old\n");
  fs::create_symlink("../elsewhere/target.csv", dir_ / "here" / "out.csv");
  fs::create_symlink("../elsewhere/new.csv", dir_ / "here" / "dangling.csv");
  for (const std::string link : {"here/out.csv", "here/dangling.csv"}) {
    const RunResult exported = Napkin({"export", "--test", "e1", "--format", "csv", "--out", link});
    ASSERT_EQ(exported.exit_code, 0) << exported.err;
  }
  const std::map<std::string, std::string> expected_here = {{"dangling.csv", "link:../elsewhere/new.csv"},
                                                            {"out.csv", "link:../elsewhere/target.csv"}};
  EXPECT_EQ(Listing(dir_ / "here"), expected_here);
  const std::string hash = util::Sha256Hex(reference);
  const std::map<std::string, std::string> expected_elsewhere = {{"new.csv", hash}, {"target.csv", hash}};
  EXPECT_EQ(Listing(dir_ / "elsewhere"), expected_elsewhere);
}

// Item 3: a FIFO is written straight into (read here while napkin writes)
// and stays a FIFO.
TEST_F(OutputDestinations, OutputIntoAFifoWritesStraightIntoIt) {
  const std::string reference = ReferenceCsv();
  const fs::path fifo = dir_ / "pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // Opened read-write so that neither this open nor napkin's blocks, and no
  // end of file is seen before napkin is done.
  const int fd = ::open(fifo.c_str(), O_RDWR | O_NONBLOCK);
  ASSERT_GE(fd, 0);
  const pid_t pid =
      StartNapkin({"--db", Db(), "export", "--test", "e1", "--format", "csv", "--out", fifo.string()},
                  dir_ / "stdout.txt", dir_ / "stderr.txt");
  std::string received;
  char buffer[65536];
  int status = 0;
  bool exited = false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (std::chrono::steady_clock::now() < deadline) {
    pollfd poll_fd{fd, POLLIN, 0};
    ::poll(&poll_fd, 1, 50);
    for (ssize_t n; (n = ::read(fd, buffer, sizeof(buffer))) > 0;)
      received.append(buffer, static_cast<size_t>(n));
    if (exited) break;  // drained after the exit
    exited = ::waitpid(pid, &status, WNOHANG) == pid;
  }
  ::close(fd);
  ASSERT_TRUE(exited);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << ReadText(dir_ / "stderr.txt");
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo)));
  EXPECT_EQ(received, reference);
}

// Item 3: as root, `--out /dev/null` replaced the device node by a regular
// file. Checked first on a private null device node (so a regression cannot
// replace the system's), then on /dev/null itself.
TEST_F(OutputDestinations, OutputIntoACharacterDeviceKeepsTheNode) {
  const fs::path node = dir_ / "null";
  if (::mknod(node.c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0)
    GTEST_SKIP() << "cannot make a device node (needs root): " << std::strerror(errno);
  RunResult exported = Napkin({"export", "--test", "e1", "--format", "csv", "--out", node.string()});
  ASSERT_EQ(exported.exit_code, 0) << exported.err;
  ASSERT_TRUE(fs::is_character_file(fs::symlink_status(node)));
  exported = Napkin({"export", "--test", "e1", "--format", "lsdyna", "--out", "/dev/null"});
  ASSERT_EQ(exported.exit_code, 0) << exported.err;
  EXPECT_TRUE(fs::is_character_file(fs::symlink_status("/dev/null")));
  const RunResult report = Napkin({"report", "--out", node.string()});
  ASSERT_EQ(report.exit_code, 0) << report.err;
  EXPECT_TRUE(fs::is_character_file(fs::symlink_status(node)));
}

// Item 3: `--out -` is standard output where the output is one file; a
// folder format refuses it, and transform sends at most one file there.
TEST_F(OutputDestinations, DashIsStandardOutputForOneFile) {
  const std::string reference = ReferenceCsv();
  const RunResult csv = Napkin({"export", "--test", "e1", "--format", "csv", "--out", "-"});
  ASSERT_EQ(csv.exit_code, 0) << csv.err;
  EXPECT_EQ(csv.out, reference);
  const RunResult report = Napkin({"report", "--out", "-"});
  ASSERT_EQ(report.exit_code, 0) << report.err;
  EXPECT_EQ(report.out.rfind("<!DOCTYPE html>", 0), 0u) << report.out.substr(0, 100);
  EXPECT_TRUE(report.out.ends_with("</html>\n"));
  EXPECT_NE(report.err.find("wrote the report to standard output: 2 tests."), std::string::npos)
      << report.err;
  const RunResult transform = RunNapkin(
      dir_.path(), {"transform", "--array", "denton-3222", "e1.csv", "--out", "t.csv", "--summary", "-"});
  ASSERT_EQ(transform.exit_code, 0) << transform.err;
  const nlohmann::json summary = nlohmann::json::parse(transform.out, nullptr, false);
  EXPECT_TRUE(summary.is_object()) << transform.out.substr(0, 200);
  EXPECT_FALSE(fs::exists(dir_ / "-"));

  const RunResult folder = Napkin({"export", "--test", "e1", "--format", "isomme", "--out", "-"});
  EXPECT_EQ(folder.exit_code, 2);
  ExpectOneSentenceError(folder, {"format isomme writes a folder", "standard output"});
  const RunResult two = RunNapkin(
      dir_.path(), {"transform", "--array", "denton-3222", "e1.csv", "--out", "-", "--summary", "-"});
  EXPECT_EQ(two.exit_code, 2);
  ExpectOneSentenceError(two, {"only one of --out, --summary and --lsdyna"});
  EXPECT_FALSE(fs::exists(dir_ / "-"));
}

// Issue 29: the destination is decided on what is opened. While `export`
// runs again and again, a second process flips the destination between two
// objects with an atomic rename; whatever napkin meets, the catalogue stays
// byte for byte, the user's files stay, and no temporary file is left.
// `flip` is called in the child with the two names to exchange.
class DestinationRace : public OutputDestinations {
 protected:
  // Runs `args` up to `tries` times or for `seconds` while a child process
  // exchanges `a` and `b` (renameat2 RENAME_EXCHANGE: both names always
  // exist). Returns how many exports exited 0.
  int RaceExports(const std::vector<std::string>& args, const fs::path& a, const fs::path& b, int tries,
                  int seconds) {
    const pid_t flipper = ::fork();
    if (flipper == 0) {
      for (;;) ::renameat2(AT_FDCWD, a.c_str(), AT_FDCWD, b.c_str(), RENAME_EXCHANGE);
    }
    int succeeded = 0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
    for (int i = 0; i < tries && std::chrono::steady_clock::now() < deadline; ++i) {
      const RunResult run = Napkin(args);
      succeeded += run.exit_code == 0;
      // Any refusal is one sentence, never an internal error.
      if (run.exit_code != 0) {
        EXPECT_EQ(run.err.find("internal error"), std::string::npos) << run.err;
      }
    }
    ::kill(flipper, SIGKILL);
    ::waitpid(flipper, nullptr, 0);
    return succeeded;
  }

  static std::vector<std::string> TemporaryFiles(const fs::path& dir) {
    std::vector<std::string> found;
    for (const auto& entry : fs::recursive_directory_iterator(dir))
      if (entry.path().filename().string().find(".tmp-") != std::string::npos ||
          entry.path().filename().string().rfind(".napkin-staging-", 0) == 0)
        found.push_back(entry.path().string());
    return found;
  }
};

// `--out out` while out flips between a character-device node and a symbolic
// link to the catalogue: the catalogue used to become the CSV (exit 0).
TEST_F(DestinationRace, ADeviceFlippedToALinkToTheCatalogueIsNeverWrittenThrough) {
  if (::mknod((dir_ / "out").c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0)
    GTEST_SKIP() << "cannot make a device node (needs root): " << std::strerror(errno);
  fs::create_symlink("lab/lab.db", dir_ / "other");
  const std::string hash = util::Sha256Hex(ReadText(Db()));
  const std::map<std::string, std::string> lab_before = Listing(lab_);
  const int succeeded = RaceExports({"export", "--test", "e1", "--format", "csv", "--out", "out"},
                                    dir_ / "out", dir_ / "other", 150, 30);
  EXPECT_GT(succeeded, 0);
  EXPECT_EQ(util::Sha256Hex(ReadText(Db())), hash);
  EXPECT_EQ(Listing(lab_), lab_before);
  EXPECT_EQ(TemporaryFiles(dir_.path()), std::vector<std::string>{});
  // Both names are still the node and the link, in some order.
  std::vector<std::string> kinds;
  for (const char* name : {"out", "other"}) {
    const fs::file_status status = fs::symlink_status(dir_ / name);
    kinds.push_back(fs::is_symlink(status) ? "link" : fs::is_character_file(status) ? "device" : "other");
  }
  std::sort(kinds.begin(), kinds.end());
  EXPECT_EQ(kinds, (std::vector<std::string>{"device", "link"}));
}

// `--out sub/lab.db` while sub flips between a decoy folder and a symbolic
// link to the catalogue's folder: the CSV used to be renamed over the
// catalogue, with `.lab.db.tmp-*` files left beside it.
TEST_F(DestinationRace, AFolderFlippedToALinkToTheCataloguesFolderIsNeverWrittenInto) {
  fs::create_directories(dir_ / "sub");
  fs::create_symlink("lab", dir_ / "other");
  const std::string hash = util::Sha256Hex(ReadText(Db()));
  const std::map<std::string, std::string> lab_before = Listing(lab_);
  const int succeeded = RaceExports({"export", "--test", "e1", "--format", "csv", "--out", "sub/lab.db"},
                                    dir_ / "sub", dir_ / "other", 150, 30);
  EXPECT_GT(succeeded, 0);
  EXPECT_EQ(util::Sha256Hex(ReadText(Db())), hash);
  EXPECT_EQ(Listing(lab_), lab_before);
  EXPECT_EQ(TemporaryFiles(dir_.path()), std::vector<std::string>{});
}

// Issue 29 item 2: every file a command reads, and every other output of the
// same command, is refused as a destination (exit 2) before anything is written.
TEST_F(OutputDestinations, ACommandsOwnInputsAndOutputsAreNeverItsDestination) {
  fs::copy_file(fs::path(NAPKIN_SOURCE_DIR) / "config" / "processing" / "default.json", dir_ / "my.json");
  fs::copy_file(fs::path(NAPKIN_SOURCE_DIR) / "config" / "arrays" / "denton-3222.json", dir_ / "array.json");
  const std::map<std::string, std::string> before = Listing(dir_.path());
  auto refused = [&](const std::vector<std::string>& args, std::initializer_list<std::string> fragments) {
    const RunResult run = Napkin(args);
    EXPECT_EQ(run.exit_code, 2) << ::testing::PrintToString(args) << run.err;
    ExpectOneSentenceError(run, fragments);
    EXPECT_EQ(Listing(dir_.path()), before) << ::testing::PrintToString(args);
  };
  const std::vector<std::string> transform = {"transform", "--array", "array.json",
                                              "--config",  "my.json", "e1.csv"};
  auto with = [&](std::vector<std::string> tail) {
    std::vector<std::string> args = transform;
    args.insert(args.end(), tail.begin(), tail.end());
    return args;
  };
  refused(with({"--out", "e1.csv"}), {"'e1.csv' is the input recording 'e1.csv' that this command reads"});
  refused(with({"--out", "./e1.csv"}), {"the input recording"});
  refused(with({"--out", "t.csv", "--summary", "my.json"}), {"the --config file 'my.json'"});
  refused(with({"--out", "array.json"}), {"the --array file 'array.json'"});
  refused(with({"--out", "t.csv", "--lsdyna", "array.json"}), {"the --array file"});
  refused(with({"--out", "x", "--summary", "x"}), {"--summary 'x' is the file --out 'x' writes"});
  refused(with({"--out", "x", "--summary", "./x"}), {"--summary './x' is the file --out 'x' writes"});
  refused({"export", "--test", "e1", "--format", "csv", "--config", "my.json", "--out", "my.json"},
          {"the --config file 'my.json'"});
  refused({"run", "--config", "my.json", "--results", "my.json"}, {"the --config file 'my.json'"});
  // Two streams may take two outputs.
  const RunResult streams = Napkin(with({"--out", "/dev/null", "--summary", "/dev/null"}));
  EXPECT_EQ(streams.exit_code, 0) << streams.err;
}

// Issue 29 item 3: an empty path is a usage error everywhere, never "no
// option" (`run --results ''` ran into the shared catalogue) nor an
// internal error.
TEST_F(OutputDestinations, AnEmptyPathIsAUsageError) {
  const std::string dump = DumpCatalogue(Db());
  const std::map<std::string, std::string> before = Listing(dir_.path());
  const std::vector<std::string> transform = {"transform", "--array", "denton-3222", "e1.csv"};
  const std::vector<std::vector<std::string>> commands = {
      {"run", "--force", "--results", ""},
      {"transform", "--array", "denton-3222", "e1.csv", "--out", "t.csv", "--summary", ""},
      {"transform", "--array", "denton-3222", "e1.csv", "--out", "t.csv", "--lsdyna", ""},
      {"transform", "--array", "denton-3222", "e1.csv", "--out", ""},
      {"transform", "--array", "", "e1.csv", "--out", "t.csv"},
      {"transform", "--array", "denton-3222", "", "--out", "t.csv"},
      {"export", "--test", "e1", "--format", "csv", "--out", ""},
      {"export", "--test", "e1", "--format", "isomme", "--out", ""},
      {"export", "--test", "e1", "--format", "csv", "--config", "", "--out", "t.csv"},
      {"report", "--out", ""},
      {"import", "--array", "denton-3222", ""},
      {"demo", "--out", ""},
      {"merge", ""},
  };
  for (const std::vector<std::string>& args : commands) {
    const RunResult run = Napkin(args);
    EXPECT_EQ(run.exit_code, 2) << ::testing::PrintToString(args) << run.err;
    ExpectOneSentenceError(run, {"must name a file or folder; it is empty"});
  }
  const RunResult db = RunNapkin(dir_.path(), {"--db", "", "query", "tests"});
  EXPECT_EQ(db.exit_code, 2) << db.err;
  ExpectOneSentenceError(db, {"--db must name a file or folder; it is empty"});
  EXPECT_EQ(Listing(dir_.path()), before);
  EXPECT_EQ(DumpCatalogue(Db()), dump);
}

// Issue 29 item 4: a folder export is all or nothing. With iso/Channel a link
// to another file system, the move used to fail half-way, leaving iso/e1.mme
// with no channels (exit 1).
TEST_F(OutputDestinations, AFolderExportIsAllOrNothing) {
  const fs::path elsewhere = fs::path("/dev/shm") / ("napkin-test-" + std::to_string(::getpid()));
  struct stat shm {
  }, here{};
  if (::stat("/dev/shm", &shm) != 0 || ::stat(dir_.path().c_str(), &here) != 0 || shm.st_dev == here.st_dev)
    GTEST_SKIP() << "needs /dev/shm on another file system than " << dir_.path();
  fs::create_directories(elsewhere);
  fs::create_directories(dir_ / "iso");
  fs::create_symlink(elsewhere, dir_ / "iso" / "Channel");
  const std::map<std::string, std::string> before = Listing(dir_.path());
  const RunResult run = Napkin({"export", "--test", "e1", "--format", "isomme", "--out", "iso"});
  EXPECT_EQ(run.exit_code, 1) << run.err;
  ExpectOneSentenceError(run, {"iso/Channel", "another file system", "nothing was exported"});
  EXPECT_EQ(Listing(dir_.path()), before);
  EXPECT_TRUE(fs::is_empty(elsewhere));
  fs::remove_all(elsewhere);
}

// Issue 29 item 5: a replaced file keeps its mode, owner and group; a new
// file gets the umask's mode. As root (CI) the owner is given back.
TEST_F(OutputDestinations, AReplacedFileKeepsItsModeAndOwner) {
  WriteText(dir_ / "private.csv", "old\n");
  ASSERT_EQ(::chmod((dir_ / "private.csv").c_str(), 0600), 0);
  const bool root = ::geteuid() == 0;
  const uid_t nobody = 65534;
  if (root) {
    ASSERT_EQ(::chown((dir_ / "private.csv").c_str(), nobody, nobody), 0);
  }
  const RunResult run = Napkin({"export", "--test", "e1", "--format", "csv", "--out", "private.csv"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  struct stat replaced {};
  ASSERT_EQ(::stat((dir_ / "private.csv").c_str(), &replaced), 0);
  EXPECT_EQ(replaced.st_mode & 07777, 0600u);
  if (root) {
    EXPECT_EQ(replaced.st_uid, nobody);
    EXPECT_EQ(replaced.st_gid, nobody);
  }
  EXPECT_NE(ReadText(dir_ / "private.csv"), "old\n");
  const mode_t mask = ::umask(0);
  ::umask(mask);
  const RunResult fresh = Napkin({"export", "--test", "e1", "--format", "csv", "--out", "fresh.csv"});
  ASSERT_EQ(fresh.exit_code, 0) << fresh.err;
  struct stat created {};
  ASSERT_EQ(::stat((dir_ / "fresh.csv").c_str(), &created), 0);
  EXPECT_EQ(created.st_mode & 07777, 0666u & ~mask);
}

// Issue 29 item 8: a missing temporary folder is a sentence naming it.
TEST_F(OutputDestinations, AMissingTemporaryFolderIsNamed) {
  // Set for napkin only (the test's own helpers use TMPDIR too).
  const RunResult run = napkin::test_support::RunProgram(
      "/usr/bin/env",
      {"TMPDIR=/nonexistent-napkin-tmp", NAPKIN_BINARY, "--db", Db(), "report", "--out", "r.html"},
      dir_.path());
  EXPECT_EQ(run.exit_code, 1) << run.err;
  ExpectOneSentenceError(run, {"the temporary folder '/nonexistent-napkin-tmp' (TMPDIR)"});
  EXPECT_FALSE(fs::exists(dir_ / "r.html"));
}

// Issue 29 item 9: the longest legal names (255 bytes) can be written; the
// temporary name used to add 22 bytes ("File name too long").
TEST_F(OutputDestinations, TheLongestLegalNamesCanBeWritten) {
  const std::string reference = ReferenceCsv();
  for (const std::size_t length : {234u, 250u, 255u}) {
    const std::string name = std::string(length - 4, 'n') + ".csv";
    const RunResult run = Napkin({"export", "--test", "e1", "--format", "csv", "--out", name});
    ASSERT_EQ(run.exit_code, 0) << length << ": " << run.err;
    EXPECT_EQ(ReadText(dir_ / name), reference);
    // Again, over the file now there.
    ASSERT_EQ(Napkin({"export", "--test", "e1", "--format", "csv", "--out", name}).exit_code, 0);
  }
  // A 246-byte test id names the files of the folder exports: "<id>.mme" (250
  // bytes), "F<id>AM00.00X" (UDS, 255 bytes).
  const std::string long_id(246, 'L');
  formats::WriteSignalsCsv(SynthNapTest(13, 0.03).signals, dir_ / "long.csv");
  ASSERT_EQ(Napkin({"import", "--array", "denton-3222", "--test-id", long_id, "long.csv"}).exit_code, 0);
  const RunResult processed = Napkin({"run", "--test", long_id});
  ASSERT_EQ(processed.exit_code, 0) << processed.err;
  for (const std::string format : {"isomme", "uds"}) {
    const RunResult run = Napkin({"export", "--test", long_id, "--format", format, "--out", format});
    ASSERT_EQ(run.exit_code, 0) << format << ": " << run.err;
    EXPECT_TRUE(
        fs::exists(dir_ / format / (format == "isomme" ? long_id + ".mme" : "F" + long_id + "AM00.00X")))
        << format;
  }
  // A UTF-8 name cut for the temporary name is cut between characters: "é" is 2 bytes.
  std::string accented;
  while (accented.size() < 250) accented += "\xc3\xa9";
  const RunResult run = Napkin({"export", "--test", "e1", "--format", "csv", "--out", accented});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(ReadText(dir_ / accented), reference);
}

// Issue 29 item 10: a demo killed while writing its stamp left
// "..napkin-demo.tmp-*" (and no stamp, in a new folder): every later demo
// refused the folder. napkin's own stale temporary files are removed.
TEST_F(OutputDestinations, AStaleStampTemporaryFileDoesNotBlockTheDemo) {
  fs::create_directories(dir_ / "fresh");
  WriteText(dir_ / "fresh" / "..napkin-demo.tmp-0123456789abcdef", "# napkin demo: half");
  RunResult demo = RunNapkin(dir_.path(), {"demo", "--out", "fresh"});
  ASSERT_EQ(demo.exit_code, 0) << demo.err;
  EXPECT_FALSE(fs::exists(dir_ / "fresh" / "..napkin-demo.tmp-0123456789abcdef"));
  // A stale one beside a complete demo's output, as a kill after the
  // earlier stamp's removal left it.
  WriteText(dir_ / "fresh" / "..napkin-demo.tmp-fedcba9876543210", "# napkin demo: half");
  demo = RunNapkin(dir_.path(), {"demo", "--out", "fresh"});
  ASSERT_EQ(demo.exit_code, 0) << demo.err;
  for (const auto& entry : fs::directory_iterator(dir_ / "fresh"))
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
}

}  // namespace
}  // namespace napkin::cli
