// Issue 11, items 5, 8, 9 and 10 (formats side): only regular files of at
// most a size ceiling are read (a FIFO named *.csv does not block, a link to
// /dev/zero is refused); large input does not flood stderr or memory (one
// warning for a million extra columns, quoted input cut to 60 characters, a
// line ceiling, name lengths); control characters are escaped by one shared
// function; a missing ISO-MME Unit is an error.
#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

#include "formats/array_json.h"
#include "formats/channel_map.h"
#include "formats/csv.h"
#include "formats/file_hash.h"
#include "formats/isomme.h"
#include "formats/json_file.h"
#include "formats/processing_config_json.h"
#include "tests/formats/formats_test_util.h"
#include "tests/support/reference_arrays.h"
#include "tests/support/test_support.h"
#include "util/text.h"

namespace napkin::formats {
namespace {

namespace fs = std::filesystem;
using test_support::ExpectInputError;
using test_support::MakeSignals;
using test_support::TempDir;
using test_support::WriteBytes;
using ::testing::HasSubstr;

const std::string kSixSlotCsvHeader = "time_s,cg_x,cg_y,cg_z,ars_x,ars_y,ars_z";

std::string GoodRows() { return "0,1,2,3,4,5,6\n0.001,1,2,3,4,5,6\n0.002,1,2,3,4,5,6\n"; }

// Writes `content` into the FIFO `path` from another thread as soon as a
// reader opens it (for up to 2 s), so a reader that waits for data is not
// blocked forever: on the unfixed code the read succeeds, on the fixed one
// the FIFO is refused before anything is read.
class FifoWriter {
 public:
  FifoWriter(const fs::path& path, std::string content)
      : thread_([this, path, content = std::move(content)] {
          const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
          while (!stop_ && std::chrono::steady_clock::now() < deadline) {
            const int fd = ::open(path.c_str(), O_WRONLY | O_NONBLOCK);
            if (fd >= 0) {
              const ssize_t written = ::write(fd, content.data(), content.size());
              (void)written;
              ::close(fd);
              return;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
          }
        }) {}
  ~FifoWriter() {
    stop_ = true;
    thread_.join();
  }

 private:
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

// --- escaping (item 9) ------------------------------------------------------

TEST(EscapeControl, ControlCharactersBecomeVisibleEscapes) {
  EXPECT_EQ(util::EscapeControl("plain text, é"), "plain text, é");
  EXPECT_EQ(util::EscapeControl("a\x1b[31mred\x1b[0m"), "a\\x1b[31mred\\x1b[0m");
  EXPECT_EQ(util::EscapeControl("line\nbreak\r\ttab\x7f"), "line\\nbreak\\r\\ttab\\x7f");
  EXPECT_EQ(util::EscapeControl(std::string("nul\0!", 5)), "nul\\x00!");
  EXPECT_EQ(util::EscapeControl("c1 \xC2\x9B"), "c1 \\u009b");  // U+009B, the 8-bit CSI
  EXPECT_FALSE(util::HasControlCharacter("Tête 11HEAD0000H3ACXA"));
  EXPECT_TRUE(util::HasControlCharacter("a\nb"));
}

TEST(Abbreviated, CutsLongInputTo60BytesAndSaysHowMuchIsLeft) {
  EXPECT_EQ(util::Abbreviated("short"), "short");
  const std::string cell(100'000, 'x');
  EXPECT_EQ(util::Abbreviated(cell), std::string(60, 'x') + "…(99940 more bytes)");
  EXPECT_EQ(util::Abbreviated("\x1b" + std::string(70, 'y')).substr(0, 5), "\\x1by");
}

TEST(CheckName, RefusesEmptyHugeAndControlCharacterNames) {
  EXPECT_NO_THROW(util::CheckName("test id", "k001 padding A (Tête)"));
  ExpectInputError([] { util::CheckName("test id", ""); }, {"test id must not be empty"});
  ExpectInputError([] { util::CheckName("series", std::string(1000, 's')); },
                   {"series", "1000 bytes long", "limited to 256 bytes"});
  ExpectInputError([] { util::CheckName("test id", "a\nb"); }, {"test id 'a\\nb'", "control character"});
}

TEST(FileNameComponent, NeverASeparatorControlCharacterDotOrDotDot) {
  EXPECT_EQ(util::FileNameComponent("k001"), "k001");
  EXPECT_EQ(util::FileNameComponent("."), "_.");
  EXPECT_EQ(util::FileNameComponent(".."), "_..");
  EXPECT_EQ(util::FileNameComponent(".hidden"), "_.hidden");
  EXPECT_EQ(util::FileNameComponent("a/b\\c:d\ne"), "a_b_c_d_e");
  EXPECT_EQ(util::FileNameComponent(""), "_");
}

// --- special files (item 5) ---------------------------------------------------

TEST(RegularFilesOnly, FifoNamedCsvIsRefusedWithoutBlocking) {
  TempDir dir;
  const fs::path fifo = dir / "pipe.csv";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const engine::ArrayGeometry array = test_support::SixAOmegaCg();
  FifoWriter writer(fifo, kSixSlotCsvHeader + "\n" + GoodRows());
  ExpectInputError([&] { ReadSignalsCsv(fifo, &array); }, {fifo.string(), "FIFO", "not a regular file"});
}

TEST(RegularFilesOnly, FifoAsJsonConfigIsRefused) {
  TempDir dir;
  const fs::path fifo = dir / "config.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  FifoWriter writer(fifo, "{}");
  ExpectInputError([&] { ReadProcessingConfig(fifo); }, {fifo.string(), "not a regular file"});
}

TEST(RegularFilesOnly, LinkToDevZeroIsRefusedByReaderAndHash) {
  if (!fs::exists("/dev/zero")) GTEST_SKIP() << "no /dev/zero";
  TempDir dir;
  const fs::path link = dir / "zero.csv";
  fs::create_symlink("/dev/zero", link);
  const engine::ArrayGeometry array = test_support::SixAOmegaCg();
  ExpectInputError([&] { ReadSignalsCsv(link, &array); }, {link.string(), "character device"});
  ExpectInputError([&] { HashPath(link); }, {link.string(), "not a regular file"});
}

TEST(RegularFilesOnly, FileBeyondTheSizeCeilingIsRefusedBeforeReading) {
  TempDir dir;
  const fs::path huge = dir / "huge.csv";
  WriteBytes(huge, "");
  // A sparse file: no disk space, and the fixed reader never reads it.
  fs::resize_file(huge, kMaxDataFileBytes + 1);
  const engine::ArrayGeometry array = test_support::SixAOmegaCg();
  ExpectInputError(
      [&] { ReadSignalsCsv(huge, &array); },
      {huge.string(), std::to_string(kMaxDataFileBytes + 1) + " bytes", "more than the 1024 MiB"});
}

TEST(RegularFilesOnly, SymbolicLinkLoopIsReportedAsALoop) {
  TempDir dir;
  fs::create_symlink(dir / "b.csv", dir / "a.csv");
  fs::create_symlink(dir / "a.csv", dir / "b.csv");
  const engine::ArrayGeometry array = test_support::SixAOmegaCg();
  ExpectInputError([&] { ReadSignalsCsv(dir / "a.csv", &array); }, {"a.csv", "loop of symbolic links"});
}

// --- floods and blow-ups (item 8) -------------------------------------------------

TEST(CsvLimits, AMillionExtraColumnsGiveOneLineNotAMillion) {
  TempDir dir;
  const engine::ArrayGeometry array = test_support::SixAOmegaCg();
  // 10^4 extra columns (a 100 KB header): one warning with the count.
  std::string header = kSixSlotCsvHeader;
  for (int i = 0; i < 10'000; ++i) header += ",x" + std::to_string(i);
  std::string rows;
  for (int k = 0; k < 3; ++k) {
    rows += std::to_string(0.001 * k) + ",1,2,3,4,5,6";
    for (int i = 0; i < 10'000; ++i) rows += ",0";
    rows += "\n";
  }
  WriteBytes(dir / "wide.csv", header + "\n" + rows);
  const CsvSignals read = ReadSignalsCsv(dir / "wide.csv", &array);
  ASSERT_EQ(read.warnings.size(), 1u);
  EXPECT_THAT(read.warnings[0],
              HasSubstr("10000 columns (\"x0\", \"x1\", \"x2\", \"x3\", \"x4\" and 9995 more)"));
  EXPECT_LT(read.warnings[0].size(), 300u);

  // 10^6 extra columns: the header line is beyond the line ceiling, one error.
  header = kSixSlotCsvHeader;
  for (int i = 0; i < 1'000'000; ++i) header += ",x" + std::to_string(i);
  WriteBytes(dir / "wider.csv", header + "\n" + GoodRows());
  try {
    ReadSignalsCsv(dir / "wider.csv", &array);
    ADD_FAILURE() << "a 7.9 MB header line must be refused";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_THAT(message, HasSubstr("line 1 is 7888929 bytes long, more than the 1 MiB"));
    EXPECT_LT(message.size(), 300u);
  }
}

TEST(CsvLimits, AHugeBadCellIsQuotedCutTo60Characters) {
  TempDir dir;
  const engine::ArrayGeometry array = test_support::SixAOmegaCg();
  const std::string cell(100'000, 'q');
  WriteBytes(dir / "cell.csv", kSixSlotCsvHeader + "\n0,1,2,3,4,5,6\n0.001,1," + cell + ",3,4,5,6\n");
  try {
    ReadSignalsCsv(dir / "cell.csv", &array);
    ADD_FAILURE() << "a non-numeric cell must be refused";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_THAT(message, HasSubstr("row 3, column \"cg_y\": \"" + std::string(60, 'q') +
                                   "…(99940 more bytes)\" is not a number."));
    EXPECT_LT(message.size(), 300u);
  }
}

TEST(CsvLimits, ControlCharactersInACellAreEscapedInTheMessage) {
  TempDir dir;
  const engine::ArrayGeometry array = test_support::SixAOmegaCg();
  WriteBytes(dir / "esc.csv", kSixSlotCsvHeader + "\n0,1,2,3,4,5,6\n0.001,1,\x1b]0;pwned\x07,3,4,5,6\n");
  try {
    ReadSignalsCsv(dir / "esc.csv", &array);
    ADD_FAILURE() << "a non-numeric cell must be refused";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_FALSE(util::HasControlCharacter(message)) << message;
    EXPECT_THAT(message, HasSubstr("\"\\x1b]0;pwned\\x07\" is not a number"));
  }
}

// Issue 11, item 10: "sampling interval inf s is not positive".
TEST(CsvLimits, AnOverflowingTimeSpanIsNotAFinitePositiveInterval) {
  TempDir dir;
  const engine::ArrayGeometry array = test_support::SixAOmegaCg();
  WriteBytes(dir / "span.csv", kSixSlotCsvHeader + "\n-1.7e308,1,2,3,4,5,6\n1.7e308,1,2,3,4,5,6\n");
  ExpectInputError([&] { ReadSignalsCsv(dir / "span.csv", &array); },
                   {"span.csv", "sampling interval inf s is not a finite positive number"});
}

TEST(NameLimits, ArrayNameOfAMegabyteIsRefused) {
  TempDir dir;
  nlohmann::json array = ArrayToJson(test_support::SixAOmegaCg());
  array["name"] = std::string(1'000'000, 'n');
  WriteBytes(dir / "array.json", array.dump());
  ExpectInputError([&] { LoadArray((dir / "array.json").string()); },
                   {"array.json", "1000000 bytes long", "limited to 256 bytes"});
  array["name"] = "bad\x1b[2Jname";
  WriteBytes(dir / "array.json", array.dump());
  ExpectInputError([&] { LoadArray((dir / "array.json").string()); }, {"control character"});
}

// --- item 10: a missing ISO-MME Unit is an error ------------------------------------

TEST(IsoMmeUnit, AChannelFeedingASlotWithoutUnitIsAnError) {
  TempDir dir;
  const engine::ArrayGeometry array = test_support::SixAOmegaCg();
  const ChannelMap map = LoadChannelMap("default");
  WriteIsoMme(MakeSignals(array, 20, 1e-4, 0.0), array, map, dir / "T1", "T1");
  const fs::path channel = dir / "T1" / "Channel" / "T1.001";
  std::string text = test_support::ReadBytes(channel);
  const std::size_t unit = text.find("Unit");
  ASSERT_NE(unit, std::string::npos);
  text.erase(unit, text.find('\n', unit) + 1 - unit);
  WriteBytes(channel, text);
  ExpectInputError([&] { ReadIsoMmeSignals(dir / "T1", array, map); },
                   {"T1.001", "no \"Unit\"", "feeds slot \"" + array.sensors[0].slot + "\""});
}

}  // namespace
}  // namespace napkin::formats
