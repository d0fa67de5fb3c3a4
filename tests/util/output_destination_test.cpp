// util/output_destination.h and util/atomic_file.h (issue 19 items
// 1-3): what each destination is resolved to, protected files refused by any
// spelling, and folder writes beside what the folder holds.
#include "util/output_destination.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <string>

#include "common/error.h"
#include "tests/formats/formats_test_util.h"
#include "tests/support/test_support.h"
#include "util/atomic_file.h"

namespace napkin::util {
namespace {

namespace fs = std::filesystem;
using test_support::ExpectInputError;
using test_support::ReadBytes;
using test_support::TempDir;
using test_support::WriteBytes;

class OutputDestinationTest : public ::testing::Test {
 protected:
  void TearDown() override { ClearOutputProtection(); }
  TempDir dir_;
};

TEST_F(OutputDestinationTest, KindsOfDestination) {
  EXPECT_EQ(ResolveOutputDestination("-").kind, OutputDestination::Kind::kStandardOutput);
  EXPECT_EQ(ResolveOutputDestination(dir_ / "new.csv").kind, OutputDestination::Kind::kFile);
  ASSERT_EQ(::mkfifo((dir_ / "fifo").c_str(), 0600), 0);
  EXPECT_EQ(ResolveOutputDestination(dir_ / "fifo").kind, OutputDestination::Kind::kStream);
  EXPECT_EQ(ResolveOutputDestination("/dev/null").kind, OutputDestination::Kind::kStream);
  // A link to a link to a file not yet there: the file it finally names.
  fs::create_directories(dir_ / "a");
  fs::create_symlink("a/target.csv", dir_ / "link1");
  fs::create_symlink("link1", dir_ / "link2");
  const OutputDestination linked = ResolveOutputDestination(dir_ / "link2");
  EXPECT_EQ(linked.kind, OutputDestination::Kind::kFile);
  EXPECT_EQ(fs::weakly_canonical(linked.path), fs::weakly_canonical(dir_ / "a" / "target.csv"));
  ExpectInputError([&] { ResolveOutputDestination(dir_ / "a"); }, {"is a folder"});
  fs::create_symlink("loop", dir_ / "loop");
  ExpectInputError([&] { ResolveOutputDestination(dir_ / "loop"); }, {"too many levels of symbolic links"});
}

TEST_F(OutputDestinationTest, AProtectedFileIsRefusedByAnyName) {
  fs::create_directories(dir_ / "lab");
  WriteBytes(dir_ / "lab" / "lab.db", "catalogue");
  fs::create_hard_link(dir_ / "lab" / "lab.db", dir_ / "hard");
  fs::create_symlink("lab/lab.db", dir_ / "soft");
  fs::create_symlink("lab/lab.db-wal", dir_ / "to-wal");
  ProtectFromOutput(dir_ / "lab" / "lab.db", "the catalogue");
  ProtectFromOutput(dir_ / "lab" / "lab.db-wal", "the log");
  for (const fs::path& name : {dir_ / "lab" / "lab.db", dir_ / "lab" / "." / "lab.db",
                               dir_ / "lab" / ".." / "lab" / "lab.db", dir_ / "hard", dir_ / "soft"}) {
    ExpectInputError([&] { WriteFileAtomically(name, [](AtomicFile& file) { file.Write("x"); }); },
                     {name.string(), "is the catalogue"});
  }
  ExpectInputError([&] { ResolveOutputDestination(dir_ / "to-wal"); }, {"is the log"});
  ExpectInputError([&] { CheckNotProtected(dir_ / "lab" / "lab.db-wal"); }, {"is the log"});
  EXPECT_EQ(ReadBytes(dir_ / "lab" / "lab.db"), "catalogue");
  EXPECT_FALSE(fs::exists(dir_ / "lab" / "lab.db-wal"));
  EXPECT_TRUE(fs::is_symlink(dir_ / "soft"));
  CheckNotProtected(dir_ / "lab" / "other.db");  // any other name is fine
}

TEST_F(OutputDestinationTest, FolderWritesGoBesideWhatTheFolderHolds) {
  const fs::path folder = dir_ / "out";
  fs::create_directories(folder / "sub");
  WriteBytes(folder / "mine.txt", "mine");
  WriteBytes(folder / "sub" / "taken.txt", "old");
  auto write = [&](const std::string& content, bool replace) {
    WriteDirectoryAtomically(
        folder,
        [&](const fs::path& staging) {
          fs::create_directories(staging / "sub");
          WriteFileAtomically(staging / "new.txt", [&](AtomicFile& file) { file.Write(content); });
          WriteFileAtomically(staging / "sub" / "taken.txt", [&](AtomicFile& file) { file.Write(content); });
        },
        replace);
  };
  // Refused before anything moves: new.txt does not appear either.
  ExpectInputError([&] { write("v1", false); }, {(folder / "sub" / "taken.txt").string(), "unless --force"});
  EXPECT_FALSE(fs::exists(folder / "new.txt"));
  EXPECT_EQ(ReadBytes(folder / "sub" / "taken.txt"), "old");
  write("v2", true);
  EXPECT_EQ(ReadBytes(folder / "sub" / "taken.txt"), "v2");
  EXPECT_EQ(ReadBytes(folder / "new.txt"), "v2");
  EXPECT_EQ(ReadBytes(folder / "mine.txt"), "mine");
  int entries = 0;
  for (const auto& entry : fs::recursive_directory_iterator(folder)) {
    EXPECT_NE(entry.path().filename().string().front(), '.') << entry.path();
    ++entries;
  }
  EXPECT_EQ(entries, 4);  // mine.txt, new.txt, sub, sub/taken.txt

  // A failing fill names the destination, not the staging folder, and a
  // folder the call created is removed again.
  ExpectInputError(
      [&] {
        WriteDirectoryAtomically(dir_ / "fresh", [](const fs::path& staging) {
          throw InputError(staging.string() + ": cannot export.");
        });
      },
      {(dir_ / "fresh").string() + ": cannot export."});
  EXPECT_FALSE(fs::exists(dir_ / "fresh"));
}

// Issue 29 item 4: when a move fails half-way, what already moved is taken
// back and a file it replaced is restored: the folder is as it was.
TEST_F(OutputDestinationTest, AFolderWriteThatFailsHalfWayLeavesTheFolderAsItWas) {
  const fs::path folder = dir_ / "out";
  fs::create_directories(folder / "sub");
  WriteBytes(folder / "a.txt", "old a");
  WriteBytes(folder / "sub" / "c.txt", "old c");
  auto fill = [](const fs::path& staging) {
    fs::create_directories(staging / "sub");
    fs::create_directories(staging / "new");
    for (const char* name : {"a.txt", "b.txt", "new/d.txt", "sub/c.txt", "sub/e.txt"})
      WriteFileAtomically(staging / name, [&](AtomicFile& file) { file.Write(std::string("new ") + name); });
  };
  // Moves in order: a.txt (replaces), b.txt, new (a whole folder), sub/c.txt (replaces), sub/e.txt.
  for (int failing = 0; failing < 5; ++failing) {
    FailFolderMoveForTesting(failing);
    ExpectInputError([&] { WriteDirectoryAtomically(folder, fill, /*replace_existing=*/true); },
                     {"cannot move the output file into place", "nothing was exported"});
    EXPECT_EQ(ReadBytes(folder / "a.txt"), "old a") << failing;
    EXPECT_EQ(ReadBytes(folder / "sub" / "c.txt"), "old c") << failing;
    int entries = 0;
    for (auto entry = fs::recursive_directory_iterator(folder); entry != fs::recursive_directory_iterator();
         ++entry)
      ++entries;
    EXPECT_EQ(entries, 3) << failing;  // a.txt, sub, sub/c.txt: nothing added, no staging folder left
  }
  FailFolderMoveForTesting(-1);
  WriteDirectoryAtomically(folder, fill, /*replace_existing=*/true);
  EXPECT_EQ(ReadBytes(folder / "a.txt"), "new a.txt");
  EXPECT_EQ(ReadBytes(folder / "new" / "d.txt"), "new new/d.txt");
  EXPECT_EQ(ReadBytes(folder / "sub" / "e.txt"), "new sub/e.txt");
}

// Issue 29 item 9: the temporary name fits whenever the final name does, and
// is recognised as the temporary file of that name.
TEST_F(OutputDestinationTest, TemporaryNamesFitWheneverTheNameDoes) {
  for (const std::size_t length : {1u, 200u, 233u, 234u, 250u, 255u}) {
    const std::string name(length, 'x');
    const std::string temporary = TemporaryNameFor(name);
    EXPECT_LE(temporary.size(), 255u) << length;
    EXPECT_TRUE(IsTemporaryNameOf(temporary, name)) << length;
    // A name cut short in its temporary name is told from a longer name with
    // the same first 233 bytes by nothing; shorter names are told apart.
    if (length < 233) {
      EXPECT_FALSE(IsTemporaryNameOf(temporary, name + "y")) << length;
    }
    EXPECT_FALSE(IsTemporaryNameOf(temporary, "y" + name.substr(1))) << length;
    EXPECT_FALSE(IsTemporaryNameOf(name, name)) << length;
  }
  std::string accented;
  while (accented.size() < 254) accented += "\xc3\xa9";
  const std::string temporary = TemporaryNameFor(accented);
  EXPECT_LE(temporary.size(), 255u);
  EXPECT_TRUE(IsTemporaryNameOf(temporary, accented));
  // No character is cut in two: what is kept of the name ends on a whole "é".
  const std::string kept = temporary.substr(1, temporary.find(".tmp-") - 1);
  EXPECT_EQ(kept.size() % 2, 0u);
}

// Issue 29 item 3: an empty path names no file.
TEST_F(OutputDestinationTest, AnEmptyPathIsRefused) {
  ExpectInputError([&] { ResolveOutputDestination(""); }, {"an empty path names no file"});
  ExpectInputError([&] { WriteDirectoryAtomically("", [](const fs::path&) {}); },
                   {"an empty path names no folder"});
}

}  // namespace
}  // namespace napkin::util
