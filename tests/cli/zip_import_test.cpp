// `napkin import` of zip archives as NHTSA publishes them (one test per
// archive, ISO-MME or UDS-1992 inside; archives written with libzip here):
// the same samples as the unpacked test, nothing left in the temporary
// folder, UDS-1992 NCHAN above 1 read with a warning, and every refusal (bad
// or corrupt archive, unsafe member name, zip bomb, several tests) one
// sentence naming the archive that leaves the catalogue identical.
#include <gtest/gtest.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

#include "formats/channel_map.h"
#include "formats/csv.h"
#include "formats/isomme.h"
#include "formats/uds1992.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"
#include "tests/support/zip_writer.h"

namespace napkin::cli {

using namespace napkin::test_support;
namespace {

// The nine NAP channels as UDS-1992 files <folder>/<stem>.001 ... .009 in
// Table 2-1 order.
void WriteUdsFiles(const engine::TestSignals& signals, const fs::path& folder, const std::string& stem,
                   formats::UdsNumberForm form) {
  fs::create_directories(folder);
  for (int c = 0; c < 9; ++c) {
    formats::UdsChannel channel;
    channel.number_form = form;
    channel.test_number = 7;
    channel.test_name = stem;
    channel.curve_name = signals.slots[static_cast<std::size_t>(c)];
    channel.nfp = static_cast<int>(std::lround(signals.t0_s / signals.dt_s));
    channel.del_s = signals.dt_s;
    channel.values.assign(signals.samples.col(c).data(), signals.samples.col(c).data() + signals.size());
    char suffix[8];
    std::snprintf(suffix, sizeof suffix, ".%03d", c + 1);
    formats::WriteUds1992(channel, folder / (stem + suffix));
  }
}

class CliZipImport : public ::testing::Test {
 protected:
  void SetUp() override {
    // The archives are unpacked under TMPDIR: a folder of the test's own, checked empty afterwards.
    fs::create_directories(dir_ / "tmp");
    const char* previous = getenv("TMPDIR");
    if (previous != nullptr) previous_tmpdir_ = previous;
    setenv("TMPDIR", (dir_ / "tmp").c_str(), 1);
    ASSERT_EQ(RunNapkin(dir_.path(), {"init"}).exit_code, 0);
  }
  void TearDown() override {
    if (previous_tmpdir_) {
      setenv("TMPDIR", previous_tmpdir_->c_str(), 1);
    } else {
      unsetenv("TMPDIR");
    }
  }

  RunResult Import(std::vector<std::string> args) {
    args.insert(args.begin(), {"import", "--array", "denton-3222"});
    return RunNapkin(dir_.path(), args);
  }

  engine::TestSignals SignalsOf(const std::string& test_id) {
    db::Catalogue catalogue = OpenForReading(dir_ / "napkin.db");
    const std::optional<db::TestId> key = catalogue.FindTestByExternalId(test_id);
    if (!key) {
      ADD_FAILURE() << "no test " << test_id;
      return {};
    }
    return catalogue.ReadTestSignals(*key);
  }

  bool TemporaryFolderIsEmpty() { return fs::is_empty(dir_ / "tmp"); }

  napkin::test_support::TempDir dir_;
  std::optional<std::string> previous_tmpdir_;
};

TEST_F(CliZipImport, IsoMmeArchiveImportsTheSameSamplesAsItsFolder) {
  const synth::SyntheticTest synth = SynthNapTest(81);
  formats::WriteIsoMme(synth.signals, synth.array, formats::LoadChannelMap("nap-example"), dir_ / "T81",
                       "T81");
  // NHTSA's layout: the test folder inside the archive; also the files at its top.
  WriteZip(dir_ / "v81iso.zip", FolderEntries(dir_ / "T81", "T81/"));
  WriteZip(dir_ / "v81top.zip", FolderEntries(dir_ / "T81"));
  const RunResult run = Import({"--channel-map", "nap-example", "T81", "v81iso.zip", "v81top.zip"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("imported 3 tests"), std::string::npos) << run.out;
  const engine::TestSignals folder = SignalsOf("T81");
  EXPECT_GT(folder.size(), 100);
  for (const char* id : {"v81iso", "v81top"}) {
    const engine::TestSignals zipped = SignalsOf(id);
    EXPECT_EQ(zipped.slots, folder.slots) << id;
    EXPECT_EQ(zipped.dt_s, folder.dt_s) << id;
    EXPECT_EQ(zipped.t0_s, folder.t0_s) << id;
    EXPECT_EQ(zipped.samples, folder.samples) << id;  // bit for bit
  }
  db::Catalogue catalogue = OpenForReading(dir_ / "napkin.db");
  const db::TestRow record = catalogue.ReadTest(*catalogue.FindTestByExternalId("v81iso"));
  EXPECT_NE(record.metadata_json.find("\"archive\":\"zip\""), std::string::npos) << record.metadata_json;
  EXPECT_NE(record.metadata_json.find("\"format\":\"iso-mme\""), std::string::npos) << record.metadata_json;
  EXPECT_TRUE(TemporaryFolderIsEmpty());

  // The same archive again is the same content: skipped.
  const RunResult again = Import({"--channel-map", "nap-example", "v81iso.zip"});
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.out.find("skipped 1"), std::string::npos) << again.out;
}

TEST_F(CliZipImport, UdsArchiveWithNchanAboveOneImportsWithAWarning) {
  const synth::SyntheticTest synth = SynthNapTest(82);
  WriteUdsFiles(synth.signals, dir_ / "uds", "v0082", formats::UdsNumberForm::kVax);
  std::vector<ZipEntry> entries = FolderEntries(dir_ / "uds");
  ASSERT_EQ(entries.size(), 9u);
  // NHTSA's files carry the test's channel count in NCHAN (file header, byte 12; VAX: little-endian).
  std::string& first = entries.front().bytes;
  first[12] = 32;
  WriteZip(dir_ / "v0082uds.zip", entries);
  // Other members (a report) are not read.
  entries.push_back({"README.TXT", "NHTSA test 82"});
  WriteZip(dir_ / "v0082all.zip", entries);

  const RunResult run = Import({"v0082uds.zip", "v0082all.zip"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("imported 2 tests"), std::string::npos) << run.out;
  EXPECT_NE(run.err.find("v0082uds.zip:v0082.001: NCHAN is 32"), std::string::npos) << run.err;
  const engine::TestSignals back = SignalsOf("v0082uds");
  ASSERT_EQ(back.size(), synth.signals.size());
  EXPECT_EQ(back.samples, synth.signals.samples.cast<float>().cast<double>());
  EXPECT_EQ(SignalsOf("v0082all").samples, back.samples);
  EXPECT_TRUE(TemporaryFolderIsEmpty());
}

class CliZipRefusal : public CliZipImport {
 protected:
  void SetUp() override {
    CliZipImport::SetUp();
    // A catalogue that already holds a test, so "identical" is not trivially true.
    const synth::SyntheticTest synth = SynthNapTest(83);
    formats::WriteIsoMme(synth.signals, synth.array, formats::LoadChannelMap("nap-example"), dir_ / "T83",
                         "T83");
    WriteZip(dir_ / "good.zip", FolderEntries(dir_ / "T83", "T83/"));
    ASSERT_EQ(Import({"--channel-map", "nap-example", "good.zip"}).exit_code, 0);
    before_ = DumpCatalogue(dir_ / "napkin.db");
  }

  void ExpectRefused(const std::string& archive, std::initializer_list<std::string> fragments) {
    const RunResult run = Import({"--channel-map", "nap-example", archive});
    EXPECT_EQ(run.exit_code, 1) << run.out;
    ExpectOneSentenceError(run, fragments);
    EXPECT_NE(run.err.find(archive), std::string::npos) << run.err;
    EXPECT_EQ(DumpCatalogue(dir_ / "napkin.db"), before_) << archive;
    EXPECT_TRUE(TemporaryFolderIsEmpty()) << archive;
    EXPECT_FALSE(fs::exists(dir_ / "evil.mme"));
    EXPECT_FALSE(fs::exists(dir_.path().parent_path() / "evil.mme"));
  }

  std::vector<ZipEntry> Members() { return FolderEntries(dir_ / "T83", "T83/"); }

  // The first channel file of `members`.
  static ZipEntry& FirstChannel(std::vector<ZipEntry>& members) {
    for (ZipEntry& entry : members)
      if (entry.name == "T83/Channel/T83.001") return entry;
    throw std::runtime_error("no channel file T83/Channel/T83.001");
  }

  std::string before_;
};

TEST_F(CliZipRefusal, PathTraversalNames) {
  std::vector<ZipEntry> parent = Members();
  parent.push_back({"../evil.mme", "Test number :evil\n"});
  WriteZip(dir_ / "parent.zip", parent);
  ExpectRefused("parent.zip", {"\"../evil.mme\"", "\"..\""});

  std::vector<ZipEntry> absolute = Members();
  absolute.push_back({(dir_ / "evil.mme").string(), "Test number :evil\n"});
  WriteZip(dir_ / "absolute.zip", absolute);
  ExpectRefused("absolute.zip", {"absolute path"});
}

TEST_F(CliZipRefusal, ZipBombs) {
  std::vector<ZipEntry> bomb = Members();
  bomb.push_back({"T83/Channel/T83.010", std::string(8 << 20, '0')});
  WriteZip(dir_ / "bomb.zip", bomb);
  ExpectRefused("bomb.zip", {"\"T83/Channel/T83.010\"", "zip bomb"});

  // A member whose headers declare fewer bytes than its data inflates to.
  std::vector<ZipEntry> liar = Members();
  WriteZip(dir_ / "liar.zip", liar);
  std::string bytes = ReadText(dir_ / "liar.zip");
  const ZipEntry& channel = FirstChannel(liar);
  std::size_t patched = 0;
  for (const std::string& signature : {std::string("PK\x03\x04", 4), std::string("PK\x01\x02", 4)}) {
    const std::size_t size_offset = signature[2] == '\x03' ? 22 : 24;
    const std::size_t name_offset = signature[2] == '\x03' ? 30 : 46;
    for (std::size_t at = bytes.find(signature); at != std::string::npos;
         at = bytes.find(signature, at + 4)) {
      if (bytes.compare(at + name_offset, channel.name.size(), channel.name) != 0) continue;
      const std::uint32_t declared = static_cast<std::uint32_t>(channel.bytes.size() / 2);
      for (int i = 0; i < 4; ++i)
        bytes[at + size_offset + static_cast<std::size_t>(i)] = static_cast<char>(declared >> (8 * i));
      ++patched;
    }
  }
  ASSERT_EQ(patched, 2u);
  WriteText(dir_ / "liar.zip", bytes);
  ExpectRefused("liar.zip", {"\"" + channel.name + "\""});
}

TEST_F(CliZipRefusal, BadAndCorruptArchivesAndSeveralTests) {
  WriteText(dir_ / "text.zip", "not an archive\n");
  ExpectRefused("text.zip", {"not a readable zip archive"});

  WriteZip(dir_ / "cut.zip", Members());
  const std::string whole = ReadText(dir_ / "cut.zip");
  WriteText(dir_ / "cut.zip", whole.substr(0, whole.size() - 30));
  ExpectRefused("cut.zip", {"not a readable zip archive"});

  // One flipped bit in a stored channel file: a CRC error.
  std::vector<ZipEntry> members = Members();
  WriteZip(dir_ / "crc.zip", members, /*store=*/true);
  std::string bytes = ReadText(dir_ / "crc.zip");
  const ZipEntry& channel = FirstChannel(members);
  const std::size_t at = bytes.find(channel.bytes.substr(channel.bytes.size() - 64));
  ASSERT_NE(at, std::string::npos);
  bytes[at + 5] = static_cast<char>(bytes[at + 5] ^ 0x01);
  WriteText(dir_ / "crc.zip", bytes);
  ExpectRefused("crc.zip", {"\"" + channel.name + "\"", "corrupt"});

  std::vector<ZipEntry> two = Members();
  for (const ZipEntry& entry : Members()) two.push_back({"copy/" + entry.name, entry.bytes});
  WriteZip(dir_ / "two.zip", two);
  ExpectRefused("two.zip", {"holds 2 tests", "one test per archive"});

  WriteZip(dir_ / "none.zip", {{"README.TXT", "nothing"}});
  ExpectRefused("none.zip", {"holds no test"});

  // A member that the reader refuses is named inside the archive.
  std::vector<ZipEntry> novalue = Members();
  FirstChannel(novalue).bytes += "NOVALUE\n";
  WriteZip(dir_ / "novalue.zip", novalue);
  ExpectRefused("novalue.zip", {"novalue.zip:T83/Channel/T83.001", "NOVALUE"});
}

// Members that libzip and the names' checks accept but the file system
// cannot hold: named "ARCHIVE.zip:MEMBER" in one sentence; before, raw
// "filesystem error: ... /tmp/napkin-zip-..." text.
TEST_F(CliZipRefusal, MembersTheFileSystemCannotHoldAreNamedInTheArchive) {
  formats::WriteSignalsCsv(SynthNapTest(84).signals, dir_ / "one.csv");
  const std::string bytes = ReadText(dir_ / "one.csv");

  WriteZip(dir_ / "nested.zip", {{"a.csv", bytes}, {"a.csv/b.csv", bytes}});
  ExpectRefused("nested.zip", {"nested.zip:a.csv/b.csv cannot be unpacked", "\"a.csv\" is a file"});

  const std::string long_name(300, 'n');
  WriteZip(dir_ / "long.zip", {{long_name + ".csv", bytes}});
  ExpectRefused("long.zip", {"long.zip:nnnnnnnn", "more bytes) cannot be unpacked (File name too long)"});

  std::string deep;
  for (int level = 0; level < 3000; ++level) deep += "d/";
  WriteZip(dir_ / "deep.zip", {{deep + "x.csv", bytes}});
  ExpectRefused("deep.zip", {"deep.zip:d/d/d/", "cannot be unpacked (File name too long)"});

  // One member under two spellings of its name.
  WriteZip(dir_ / "spelled.zip", {{"t/a.csv", bytes}, {"t/./a.csv", bytes}});
  ExpectRefused("spelled.zip", {"spelled.zip:t/./a.csv is in the archive twice"});
  // The same name twice (written under a stand-in name, renamed in both headers): libzip refuses the archive.
  WriteZip(dir_ / "twice.zip", {{"a.csv", bytes}, {"b.csv", bytes}});
  std::string zip = ReadText(dir_ / "twice.zip");
  for (std::size_t at = zip.find("b.csv"); at != std::string::npos; at = zip.find("b.csv", at + 1))
    zip[at] = 'a';
  WriteText(dir_ / "twice.zip", zip);
  ExpectRefused("twice.zip", {"twice.zip: "});

  for (const char* archive : {"nested.zip", "long.zip", "deep.zip", "spelled.zip", "twice.zip"}) {
    const RunResult run = Import({archive});
    EXPECT_EQ(run.err.find("napkin-zip-"), std::string::npos) << run.err;
    EXPECT_EQ(run.err.find("filesystem error"), std::string::npos) << run.err;
  }
}

// docs/formats.md "Zip archives": the temporary folder is removed whatever
// happens, SIGTERM and SIGINT during the import included (before: the
// folder and the unpacked member were left in $TMPDIR). The process then
// ends by the signal, and the catalogue is as before.
TEST_F(CliZipImport, ASignalDuringTheImportRemovesTheTemporaryFolder) {
  // SIGINT may be ignored by whoever started the tests (a background job); napkin keeps
  // an ignored signal ignored, so give the child the default.
  signal(SIGINT, SIG_DFL);
  // A CSV test of 40 MB, stored: unpacking and reading it take long enough to be interrupted.
  const engine::TestSignals signals = SynthNapTest(85).signals;
  formats::WriteSignalsCsv(signals, dir_ / "small.csv");
  const std::string small = ReadText(dir_ / "small.csv");
  std::string csv = small.substr(0, small.find('\n') + 1);
  const std::size_t columns = static_cast<std::size_t>(std::count(csv.begin(), csv.end(), ','));
  std::string zeros;
  for (std::size_t c = 0; c < columns; ++c) zeros += ",0.125";
  for (int row = 0; csv.size() < (std::size_t{40} << 20); ++row)
    csv += util::FormatNumber(row * 1e-4) + zeros + "\n";
  WriteZip(dir_ / "big.zip", {{"big.csv", csv}}, /*store=*/true);
  const std::string before = DumpCatalogue(dir_ / "napkin.db");

  for (const int signal_number : {SIGTERM, SIGINT}) {
    SCOPED_TRACE(signal_number == SIGTERM ? "SIGTERM" : "SIGINT");
    const pid_t pid = StartNapkin({"--db", (dir_ / "napkin.db").string(), "import", "--array", "denton-3222",
                                   (dir_ / "big.zip").string()},
                                  dir_ / "out.txt", dir_ / "err.txt");
    ASSERT_GT(pid, 0);
    // Wait until the member is unpacked in full, then interrupt the import.
    bool unpacked = false;
    for (int wait = 0; wait < 60000 && !unpacked; ++wait) {
      for (const auto& entry : fs::directory_iterator(dir_ / "tmp")) {
        std::error_code error;
        unpacked |= fs::file_size(entry.path() / "big.csv", error) == csv.size();
      }
      if (!unpacked) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ASSERT_TRUE(unpacked) << ReadText(dir_ / "err.txt");
    ASSERT_EQ(kill(pid, signal_number), 0);
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == signal_number)
        << "status " << status << ", stderr: " << ReadText(dir_ / "err.txt");
    EXPECT_TRUE(TemporaryFolderIsEmpty());
    for (const auto& entry : fs::directory_iterator(dir_ / "tmp")) ADD_FAILURE() << "left: " << entry.path();
    EXPECT_EQ(DumpCatalogue(dir_ / "napkin.db"), before);
  }
}

}  // namespace
}  // namespace napkin::cli
