// formats::ZipArchive: members read back byte for byte; unsafe names,
// zip bombs (declared against actual size, size ceilings, compression
// ratio) and damaged archives refused with one sentence naming the archive
// and the member.
#include "formats/zip_archive.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <sstream>

#include "common/error.h"
#include "tests/support/run_command.h"
#include "tests/support/test_support.h"
#include "tests/support/zip_writer.h"

namespace napkin::formats {
namespace {

namespace fs = std::filesystem;
using test_support::ReadText;
using test_support::WriteZip;
using test_support::ZipEntry;

void WriteBinary(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

// The message of the InputError `action` throws ("" when it throws none).
template <typename Action>
std::string Refusal(Action action) {
  try {
    action();
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

void ExpectMentions(const std::string& message, std::initializer_list<std::string> fragments) {
  ASSERT_FALSE(message.empty()) << "no error";
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_EQ(message.back(), '.') << message;
  for (const std::string& fragment : fragments)
    EXPECT_NE(message.find(fragment), std::string::npos) << message << "\nmissing: " << fragment;
}

// Little-endian 32-bit field of a zip header.
void PatchWord(std::string& bytes, std::size_t offset, std::uint32_t value) {
  for (int i = 0; i < 4; ++i)
    bytes[offset + static_cast<std::size_t>(i)] = static_cast<char>(value >> (8 * i));
}
std::uint32_t WordAt(const std::string& bytes, std::size_t offset) {
  std::uint32_t value = 0;
  for (int i = 3; i >= 0; --i)
    value = (value << 8) | static_cast<unsigned char>(bytes[offset + static_cast<std::size_t>(i)]);
  return value;
}

// Offsets of the one member's local header and central directory entry
// (signatures PK\3\4 and PK\1\2, APPNOTE 4.3.7 and 4.3.12).
std::size_t LocalHeader(const std::string& bytes) { return bytes.find(std::string("PK\x03\x04", 4)); }
std::size_t CentralEntry(const std::string& bytes) { return bytes.find(std::string("PK\x01\x02", 4)); }

std::string Noise(std::size_t size, std::uint32_t seed) {
  std::string text;
  std::uint32_t state = seed;
  while (text.size() < size) {
    state = state * 1664525u + 1013904223u;
    text += std::to_string(state % 100000) + "\n";
  }
  text.resize(size);
  return text;
}

class ZipArchiveTest : public ::testing::Test {
 protected:
  test_support::TempDir dir_;
};

TEST(UnsafeMemberName, RefusesAbsolutePathsDriveLettersAndParentComponents) {
  for (const char* safe : {"a.mme", "T1/Channel/T1.001", "./x.csv", "..a/b..", "dir/"})
    EXPECT_FALSE(UnsafeMemberName(safe)) << safe;
  for (const char* unsafe :
       {"/etc/passwd", "\\x.mme", "C:/x.mme", "c:x", "../x.mme", "a/../../x", "a\\..\\x", "a/..", "", "a\nb"})
    EXPECT_TRUE(UnsafeMemberName(unsafe)) << unsafe;
}

TEST_F(ZipArchiveTest, MembersReadBackByteForByte) {
  const std::vector<ZipEntry> entries = {{"T1/T1.mme", "Test number :T1\r\n"},
                                         {"T1/Channel/T1.001", Noise(300'000, 7)},
                                         {"T1/Channel/empty.txt", ""}};
  WriteZip(dir_ / "t.zip", entries);
  ZipArchive zip(dir_ / "t.zip");
  ASSERT_EQ(zip.members().size(), 3u);
  for (std::size_t i = 0; i < entries.size(); ++i) {
    EXPECT_EQ(zip.members()[i].name, entries[i].name);
    EXPECT_EQ(zip.members()[i].size, entries[i].bytes.size());
    EXPECT_EQ(zip.Read(zip.members()[i]), entries[i].bytes);
  }
  EXPECT_LT(zip.members()[1].compressed_size, zip.members()[1].size);  // deflated
}

TEST_F(ZipArchiveTest, UnsafeNamesAreRefusedWhenTheArchiveIsOpened) {
  for (const std::string name : {"../evil.mme", "/tmp/evil.mme", "T1/../../evil.001"}) {
    WriteZip(dir_ / "bad.zip", {{"T1/T1.mme", "x"}, {name, "y"}});
    ExpectMentions(Refusal([&] { ZipArchive zip(dir_ / "bad.zip"); }),
                   {(dir_ / "bad.zip").string(), "\"" + name + "\"", "refuses"});
  }
}

TEST_F(ZipArchiveTest, DataInflatingBeyondItsDeclaredSizeIsRefused) {
  const std::string data = Noise(100'000, 3);
  WriteZip(dir_ / "liar.zip", {{"v.001", data}});
  std::string bytes = ReadText(dir_ / "liar.zip");
  // Declare 1,000 bytes uncompressed in both headers (local: offset 22; central: 24).
  ASSERT_EQ(WordAt(bytes, LocalHeader(bytes) + 22), data.size());
  ASSERT_EQ(WordAt(bytes, CentralEntry(bytes) + 24), data.size());
  PatchWord(bytes, LocalHeader(bytes) + 22, 1000);
  PatchWord(bytes, CentralEntry(bytes) + 24, 1000);
  WriteBinary(dir_ / "liar.zip", bytes);
  const std::string message = Refusal([&] {
    ZipArchive zip(dir_ / "liar.zip");
    zip.Read(zip.members().front());
  });
  ExpectMentions(message, {(dir_ / "liar.zip").string(), "\"v.001\""});
}

TEST_F(ZipArchiveTest, DataShorterThanDeclaredIsRefused) {
  const std::string data = Noise(10'000, 5);
  WriteZip(dir_ / "short.zip", {{"v.001", data}}, /*store=*/true);
  std::string bytes = ReadText(dir_ / "short.zip");
  PatchWord(bytes, LocalHeader(bytes) + 22, 20'000);
  PatchWord(bytes, CentralEntry(bytes) + 24, 20'000);
  WriteBinary(dir_ / "short.zip", bytes);
  const std::string message = Refusal([&] {
    ZipArchive zip(dir_ / "short.zip");
    zip.Read(zip.members().front());
  });
  ExpectMentions(message, {(dir_ / "short.zip").string(), "\"v.001\""});
}

TEST_F(ZipArchiveTest, CeilingsOnMemberTotalAndRatioRefuseBombs) {
  // 4 MB of one repeated line deflates to a few kB: a ratio far above 200.
  WriteZip(dir_ / "bomb.zip", {{"v.001", std::string(4 << 20, '0')}});
  {
    ZipArchive zip(dir_ / "bomb.zip");
    ExpectMentions(Refusal([&] { zip.Read(zip.members().front()); }),
                   {(dir_ / "bomb.zip").string(), "\"v.001\"", "zip bomb"});
  }
  WriteZip(dir_ / "two.zip", {{"a.001", Noise(60'000, 1)}, {"a.002", Noise(60'000, 2)}});
  ZipLimits member_limit;
  member_limit.max_member_bytes = 50'000;
  {
    ZipArchive zip(dir_ / "two.zip", member_limit);
    ExpectMentions(Refusal([&] { zip.Read(zip.members().front()); }),
                   {(dir_ / "two.zip").string(), "\"a.001\"", "60000 bytes", "50000 bytes"});
  }
  ZipLimits total_limit;
  total_limit.max_total_bytes = 100'000;
  ZipArchive zip(dir_ / "two.zip", total_limit);
  EXPECT_EQ(zip.Read(zip.members()[0]).size(), 60'000u);
  ExpectMentions(Refusal([&] { zip.Read(zip.members()[1]); }),
                 {(dir_ / "two.zip").string(), "\"a.002\"", "100000 bytes"});
}

TEST_F(ZipArchiveTest, CorruptDataAndNonArchivesAreRefused) {
  const std::string data = Noise(5'000, 9);
  WriteZip(dir_ / "crc.zip", {{"v.001", data}}, /*store=*/true);
  std::string bytes = ReadText(dir_ / "crc.zip");
  const std::size_t at = bytes.find(data.substr(0, 40));
  ASSERT_NE(at, std::string::npos);
  bytes[at + 10] = static_cast<char>(bytes[at + 10] ^ 0x01);  // one bit of the stored data
  WriteBinary(dir_ / "crc.zip", bytes);
  ExpectMentions(Refusal([&] {
                   ZipArchive zip(dir_ / "crc.zip");
                   zip.Read(zip.members().front());
                 }),
                 {(dir_ / "crc.zip").string(), "\"v.001\"", "corrupt"});

  WriteBinary(dir_ / "text.zip", "this is not an archive\n");
  ExpectMentions(Refusal([&] { ZipArchive zip(dir_ / "text.zip"); }),
                 {(dir_ / "text.zip").string(), "not a readable zip archive"});

  WriteZip(dir_ / "cut.zip", {{"v.001", Noise(50'000, 4)}});
  const std::string whole = ReadText(dir_ / "cut.zip");
  WriteBinary(dir_ / "cut.zip", whole.substr(0, whole.size() / 2));
  ExpectMentions(Refusal([&] { ZipArchive zip(dir_ / "cut.zip"); }),
                 {(dir_ / "cut.zip").string(), "not a readable zip archive"});
}

// ZipArchiveBytes (the service's folder exports): read back by ZipArchive member for member, byte
// for byte, in the order given; the same members give the same bytes, another member other bytes.
TEST(ZipArchiveBytes, ReadsBackAndTheSameMembersGiveTheSameBytes) {
  const test_support::TempDir dir;
  std::string large;
  for (int i = 0; i < 20000; ++i) large += std::to_string(i * 7919 % 10007) + (i % 13 == 0 ? "\n" : ",");
  const std::vector<ZipMemberBytes> members = {
      {"T1.mme", "Data format        :ISO-MME\n"}, {"Channel/T1.chn", large}, {"Channel/empty.001", ""}};
  const std::string bytes = ZipArchiveBytes(members);
  EXPECT_EQ(ZipArchiveBytes(members), bytes);
  WriteBinary(dir / "a.zip", bytes);
  ZipArchive archive(dir / "a.zip");
  ASSERT_EQ(archive.members().size(), members.size());
  for (std::size_t i = 0; i < members.size(); ++i) {
    EXPECT_EQ(archive.members()[i].name, members[i].name);
    EXPECT_EQ(archive.Read(archive.members()[i]), members[i].bytes) << members[i].name;
  }
  EXPECT_LT(bytes.size(), large.size()) << "deflated";
  std::vector<ZipMemberBytes> other = members;
  other[1].bytes.back() = ';';
  EXPECT_NE(ZipArchiveBytes(other), bytes);
  WriteBinary(dir / "empty.zip", ZipArchiveBytes({}));
  EXPECT_TRUE(ZipArchive(dir / "empty.zip").members().empty());
}

}  // namespace
}  // namespace napkin::formats
