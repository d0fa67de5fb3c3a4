#include "formats/uds1992.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <new>
#include <ostream>
#include <string>
#include <vector>

#include "formats/channel_map.h"
#include "tests/formats/formats_test_util.h"
#include "tests/support/named_cases.h"
#include "tests/support/reference_arrays.h"
#include "tests/support/test_support.h"

namespace napkin::formats {
namespace {

using test_support::ExpectInputError;
using test_support::TempDir;

// A UDS-1992 file is a sequence of 512-byte records (header, curve header, data).
constexpr std::size_t kRecordBytes = 512;

// VAX F_floating: bit 15 sign, bits 14-7 excess-128 exponent, fraction 0.1f
// with hidden bit; words little-endian, high-order word first. The longword
// of 1.0 is 0x00004080, stored as bytes 80 40 00 00.
struct VaxBitsCase {
  const char* name;
  double value;
  std::array<std::uint8_t, 4> bytes;
};
void PrintTo(const VaxBitsCase& bits, std::ostream* os) { *os << bits.name << " (" << bits.value << ")"; }

class VaxBitPatternTest : public ::testing::TestWithParam<VaxBitsCase> {};

TEST_P(VaxBitPatternTest, DecodesAndEncodes) {
  const VaxBitsCase& c = GetParam();
  double decoded = -42.0;
  EXPECT_TRUE(DecodeVaxF(c.bytes.data(), decoded));
  EXPECT_EQ(decoded, c.value);
  std::uint8_t encoded[4];
  ASSERT_TRUE(EncodeVaxF(static_cast<float>(c.value), encoded)) << c.value;
  EXPECT_EQ(std::memcmp(encoded, c.bytes.data(), 4), 0) << c.value;
}

INSTANTIATE_TEST_SUITE_P(
    Known, VaxBitPatternTest,
    ::testing::Values(VaxBitsCase{"one", 1.0, {0x80, 0x40, 0x00, 0x00}},
                      VaxBitsCase{"minus_one", -1.0, {0x80, 0xC0, 0x00, 0x00}},
                      VaxBitsCase{"half", 0.5, {0x00, 0x40, 0x00, 0x00}},
                      VaxBitsCase{"three", 3.0, {0x40, 0x41, 0x00, 0x00}},
                      VaxBitsCase{"zero", 0.0, {0x00, 0x00, 0x00, 0x00}},
                      // 0.1f: IEEE 0x3DCCCCCD -> VAX exponent + 2 -> longword 0xCCCD3ECC.
                      VaxBitsCase{"one_tenth", static_cast<double>(0.1f), {0xCC, 0x3E, 0xCD, 0xCC}},
                      // Largest F_floating: 0.111...1 * 2^127 = (1 - 2^-24) * 2^127.
                      VaxBitsCase{
                          "largest", std::ldexp(1.0 - std::ldexp(1.0, -24), 127), {0xFF, 0x7F, 0xFF, 0xFF}},
                      // Smallest positive F_floating: 0.5 * 2^-127 = 2^-128.
                      VaxBitsCase{"smallest_positive", std::ldexp(1.0, -128), {0x80, 0x00, 0x00, 0x00}}),
    test_support::CaseName());

TEST(VaxFloatTest, ReservedOperandAndOverflowAreRefused) {
  const std::uint8_t reserved_operand[4] = {0x00, 0x80, 0x12, 0x34};
  double value = 0.0;
  EXPECT_FALSE(DecodeVaxF(reserved_operand, value));
  std::uint8_t out[4];
  EXPECT_FALSE(EncodeVaxF(3.0e38f, out));  // beyond the F_floating range
}

TEST(VaxFloatTest, EveryExponentRoundTrips) {
  for (int e = -120; e <= 120; e += 3)
    for (const float mantissa : {1.0f, 1.5f, 1.9999999f, 1.2345678f}) {
      const float value = std::ldexp(mantissa, e) * ((e % 2) ? -1.0f : 1.0f);
      std::uint8_t bytes[4];
      ASSERT_TRUE(EncodeVaxF(value, bytes));
      double decoded = 0.0;
      ASSERT_TRUE(DecodeVaxF(bytes, decoded));
      EXPECT_EQ(decoded, static_cast<double>(value));
    }
}

UdsChannel MakeChannel(UdsNumberForm form, int nfp, std::size_t count) {
  UdsChannel channel;
  channel.number_form = form;
  channel.test_number = 1234;
  channel.test_name = "V0001";
  channel.title = "napkin round trip";
  channel.curve_name = "HEAD CG X";
  channel.senatt = "HEAD CG";
  channel.axis = "XL";
  channel.nfp = nfp;
  channel.del_s = 1e-4;
  for (std::size_t i = 0; i < count; ++i)
    channel.values.push_back(static_cast<double>(static_cast<float>(std::sin(0.01 * i) * 150.0 - 3.25)));
  return channel;
}

class UdsRoundTripTest : public ::testing::TestWithParam<UdsNumberForm> {};

TEST_P(UdsRoundTripTest, IdenticalSamplesAndHeader) {
  TempDir dir;
  for (const std::size_t count : {1u, 125u, 126u, 1001u}) {
    const UdsChannel written = MakeChannel(GetParam(), -100, count);
    const auto path = dir / "v0001.001";
    WriteUds1992(written, path);
    EXPECT_EQ(std::filesystem::file_size(path), (2 + (count + 124) / 125) * 512);
    const UdsChannel read = ReadUds1992(path);
    EXPECT_EQ(read.number_form, GetParam());
    EXPECT_EQ(read.values, written.values);
    EXPECT_EQ(read.nfp, -100);
    EXPECT_EQ(read.nlp(), -100 + static_cast<int>(count) - 1);
    EXPECT_EQ(read.del_s, 1e-4);  // the REAL*4 DEL read as the decimal it stands for
    EXPECT_EQ(read.test_number, 1234);
    EXPECT_EQ(read.test_name, "V0001");
    EXPECT_EQ(read.senatt, "HEAD CG");
    EXPECT_EQ(read.axis, "XL");
    EXPECT_EQ(read.yunits, "G'S");
    const RawChannel raw = ToRawChannel(read, path);
    EXPECT_DOUBLE_EQ(raw.t0_s, -0.01);
  }
}

INSTANTIATE_TEST_SUITE_P(AllNumberForms, UdsRoundTripTest,
                         ::testing::Values(UdsNumberForm::kIeee, UdsNumberForm::kVax, UdsNumberForm::kSun),
                         [](const ::testing::TestParamInfo<UdsNumberForm>& info) -> std::string {
                           switch (info.param) {
                             case UdsNumberForm::kIeee:
                               return "Ieee";
                             case UdsNumberForm::kVax:
                               return "Vax";
                             case UdsNumberForm::kSun:
                               return "Sun";
                           }
                           return "Unknown";
                         });

// A file laid out by hand at the NHTSA UDS library's byte offsets,
// independent of the writer: FILEVER@0, NCHAN@12, FILEFORM@16, NUMFORM@26,
// TSTNO@49; curve header: SENATT@42, AXIS@86, YUNITS@108, NFP@278, NLP@282,
// DEL@286; data after a 12-byte record header.
TEST(UdsLayoutTest, ReadsHandBuiltSunFile) {
  std::string bytes(4 * kRecordBytes, ' ');
  auto put = [&](std::size_t offset, const std::string& text) { bytes.replace(offset, text.size(), text); };
  auto put_be = [&](std::size_t offset, std::uint32_t word) {
    for (int i = 0; i < 4; ++i) bytes[offset + i] = static_cast<char>(word >> (24 - 8 * i));
  };
  put(0, "UDS-1992");
  put_be(12, 1);
  put(16, "Y");
  put(26, "SUN");
  put(31, "MET");
  put_be(49, 77);
  put(512, "CURVE HDR");
  put(512 + 42, "HEAD Y ARM");
  put(512 + 86, "ZL");
  put(512 + 108, "G'S");
  put_be(512 + 278, 0);
  put_be(512 + 282, 129);         // 130 samples: two data records
  put_be(512 + 286, 0x3A83126F);  // 0.001f
  for (int r = 0; r < 2; ++r) {
    put(1024 + r * 512, "Y DATA      ");
    for (int i = 0; i < 125; ++i)
      put_be(1024 + r * 512 + 12 + 4 * i, std::bit_cast<std::uint32_t>(float(r * 125 + i)));
  }
  TempDir dir;
  test_support::WriteBytes(dir / "t.002", bytes);
  const UdsChannel channel = ReadUds1992(dir / "t.002");
  EXPECT_EQ(channel.test_number, 77);
  EXPECT_EQ(channel.senatt, "HEAD Y ARM");
  EXPECT_EQ(channel.axis, "ZL");
  EXPECT_EQ(channel.del_s, 0.001);
  ASSERT_EQ(channel.values.size(), 130u);
  for (int i = 0; i < 130; ++i) EXPECT_EQ(channel.values[i], i);
}

// Replaces `text.size()` bytes at `offset`.
std::string Replaced(std::string bytes, std::size_t offset, const std::string& text) {
  bytes.replace(offset, text.size(), text);
  return bytes;
}

// Writes `value`'s bytes (host order, little-endian: the IEEE form) at `offset`.
template <typename T>
std::string Poked(std::string bytes, std::size_t offset, T value) {
  std::memcpy(&bytes[offset], &value, sizeof(value));
  return bytes;
}

// A spoilt copy of a good IEEE file of 4 data records (400 samples), and
// what the message must mention besides the file.
struct UdsErrorCase {
  const char* name;  // also the file's stem
  std::string (*spoil)(const std::string& good);
  std::vector<std::string> fragments;
};
void PrintTo(const UdsErrorCase& error, std::ostream* os) { *os << error.name << ".001"; }

class UdsErrorTest : public ::testing::TestWithParam<UdsErrorCase> {};

TEST_P(UdsErrorTest, NamesTheFile) {
  TempDir dir;
  const auto good = dir / "good.001";
  WriteUds1992(MakeChannel(UdsNumberForm::kIeee, 0, 400), good);  // 4 data records
  const auto path = dir / (std::string(GetParam().name) + ".001");
  test_support::WriteBytes(path, GetParam().spoil(test_support::ReadBytes(good)));
  std::vector<std::string> all = {path.string()};
  all.insert(all.end(), GetParam().fragments.begin(), GetParam().fragments.end());
  ExpectInputError([&] { ReadUds1992(path); }, all);
}

INSTANTIATE_TEST_SUITE_P(
    SpoiltFiles, UdsErrorTest,
    ::testing::Values(
        UdsErrorCase{"truncated",
                     [](const std::string& good) { return good.substr(0, 5 * kRecordBytes + 312); },
                     {"data record 4 is truncated (312 of 512 bytes)"}},
        UdsErrorCase{"missing",
                     [](const std::string& good) { return good.substr(0, 4 * kRecordBytes); },
                     {"data record 3 is missing"}},
        UdsErrorCase{"short_header",
                     [](const std::string& good) { return good.substr(0, 100); },
                     {"file header", "truncated (100 of 512 bytes)"}},
        UdsErrorCase{"no_curve",
                     [](const std::string& good) { return good.substr(0, 512); },
                     {"curve header", "missing"}},
        UdsErrorCase{"version",
                     [](const std::string& good) { return Replaced(good, 0, "UDS-1991"); },
                     {"FILEVER is \"UDS-1991\""}},
        UdsErrorCase{"numform",
                     [](const std::string& good) { return Replaced(good, 26, "CRAY "); },
                     {"unknown NUMFORM \"CRAY\""}},
        UdsErrorCase{"crossed",
                     [](const std::string& good) { return Poked(good, 512 + 282, std::int32_t{-5}); },
                     {"NLP -5 is less than NFP 0"}},
        UdsErrorCase{"record",
                     [](const std::string& good) { return Replaced(good, 3 * kRecordBytes, "X DATA"); },
                     {"data record 2 starts with \"X DATA\""}},
        UdsErrorCase{"curve",
                     [](const std::string& good) { return Replaced(good, 512, "CURVE XXX"); },
                     {"record 2 starts with \"CURVE XXX\""}},
        UdsErrorCase{"nan",
                     [](const std::string& good) {
                       return Poked(good, 2 * kRecordBytes + 12 + 4 * 7,
                                    std::numeric_limits<float>::quiet_NaN());
                     },
                     {"sample 7", "not a finite number"}},
        // Issue 11, item 2: a 1 KB file (the two headers) declaring NLP 99,999,999.
        UdsErrorCase{"absurd_nlp",
                     [](const std::string& good) {
                       return Poked(good.substr(0, 2 * kRecordBytes), 512 + 282, std::int32_t{99'999'999});
                     },
                     {"data record 1 is missing", "NLP 99999999 needs 800000 data records",
                      "the file of 1024 bytes holds 0"}}),
    test_support::CaseName());

// Issue 11, item 2: the declared count is checked against the file's size before the samples are
// allocated, so the 1 KB file with NLP 99,999,999 (800 MB of samples) is refused under an
// address-space limit of 64 MB above what the process already maps. Run in a child process so
// the limit does not outlive the test.
TEST(UdsSizeTest, DeclaredCountIsCheckedBeforeAllocating) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "an address-space limit cannot be set under AddressSanitizer";
#else
  TempDir dir;
  const auto good = dir / "good.001";
  WriteUds1992(MakeChannel(UdsNumberForm::kIeee, 0, 400), good);
  const auto path = dir / "absurd_nlp.001";
  test_support::WriteBytes(path, Poked(test_support::ReadBytes(good).substr(0, 2 * kRecordBytes), 512 + 282,
                                       std::int32_t{99'999'999}));
  std::fflush(nullptr);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    long mapped_pages = 0;
    if (std::FILE* statm = std::fopen("/proc/self/statm", "r")) {
      if (std::fscanf(statm, "%ld", &mapped_pages) != 1) mapped_pages = 0;
      std::fclose(statm);
    }
    if (mapped_pages <= 0) _exit(4);
    const rlim_t limit =
        static_cast<rlim_t>(mapped_pages) * static_cast<rlim_t>(sysconf(_SC_PAGESIZE)) + (rlim_t{64} << 20);
    const rlimit address_space{limit, limit};
    if (setrlimit(RLIMIT_AS, &address_space) != 0) _exit(4);
    try {
      ReadUds1992(path);
    } catch (const InputError&) {
      _exit(0);  // refused as it should be
    } catch (const std::bad_alloc&) {
      _exit(2);  // allocated the declared count first
    } catch (...) {
      _exit(3);
    }
    _exit(1);  // accepted
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0)
      << "1: accepted, 2: std::bad_alloc, 3: another exception, 4: no limit set";
#endif
}

TEST(UdsVaxErrorTest, ReservedOperandNamesFileAndSample) {
  TempDir dir;
  UdsChannel vax = MakeChannel(UdsNumberForm::kVax, 0, 10);
  WriteUds1992(vax, dir / "vax.001");
  std::string reserved = test_support::ReadBytes(dir / "vax.001");
  reserved[2 * kRecordBytes + 12 + 4 * 3] = 0x00;
  reserved[2 * kRecordBytes + 12 + 4 * 3 + 1] = static_cast<char>(0x80);
  const auto path = dir / "reserved.001";
  test_support::WriteBytes(path, reserved);
  ExpectInputError([&] { ReadUds1992(path); }, {path.string(), "sample 3", "VAX reserved operand"});
}

TEST(UdsGroupTest, GroupsFilesOfOneTestByStem) {
  const std::vector<std::filesystem::path> files = {"data/v0002.001", "data/v0001.009", "data/v0001.001",
                                                    "data/v0002.002", "data/v0001.005"};
  const auto groups = GroupUdsFilesByStem(files);
  ASSERT_EQ(groups.size(), 2u);
  EXPECT_EQ(groups[0].first, "v0001");
  EXPECT_EQ(groups[0].second,
            (std::vector<std::filesystem::path>{"data/v0001.001", "data/v0001.005", "data/v0001.009"}));
  EXPECT_EQ(groups[1].first, "v0002");
  EXPECT_EQ(groups[1].second.size(), 2u);
}

// Writes the nine channels of a NAP test as UDS-1992 files v0001.001 ... .009.
std::vector<std::filesystem::path> WriteNapTest(const TempDir& dir, const engine::TestSignals& signals,
                                                UdsNumberForm form, const ChannelMap* map) {
  std::vector<std::filesystem::path> files;
  for (int i = 0; i < 9; ++i) {
    UdsChannel channel;
    channel.number_form = form;
    channel.del_s = signals.dt_s;
    channel.nfp = static_cast<int>(std::lround(signals.t0_s / signals.dt_s));
    if (map != nullptr) {
      channel.senatt = map->Find(signals.slots[i])->senatt;
      channel.axis = map->Find(signals.slots[i])->axis;
    }
    channel.values.assign(signals.samples.col(i).data(), signals.samples.col(i).data() + signals.size());
    char name[32];
    std::snprintf(name, sizeof(name), "v0001.%03d", i + 1);
    files.push_back(dir / name);
    WriteUds1992(channel, files.back());
  }
  return files;
}

TEST(UdsTestReadTest, NineFilesInTable21OrderWithoutMap) {
  TempDir dir;
  const engine::ArrayGeometry array = test_support::Denton3222();
  const engine::TestSignals written = test_support::MakeSignals(array, 700, 1e-4, 0.0, true);
  std::vector<std::filesystem::path> files = WriteNapTest(dir, written, UdsNumberForm::kVax, nullptr);
  std::reverse(files.begin(), files.end());  // order of the arguments does not matter; names do
  const engine::TestSignals read = ReadUdsTest(files, array, nullptr, "v0001");
  EXPECT_EQ(read.slots, written.slots);
  EXPECT_TRUE((read.samples.array() == written.samples.array()).all());
  EXPECT_EQ(read.dt_s, 1e-4);
  files.pop_back();
  ExpectInputError([&] { ReadUdsTest(files, array, nullptr, "v0001"); }, {"test v0001", "8 UDS-1992 files"});
}

TEST(UdsTestReadTest, SlotsFromSenattAndAxisThroughTheMap) {
  TempDir dir;
  const engine::ArrayGeometry array = test_support::Denton3222();
  const ChannelMap map = LoadChannelMap("nap-example");
  // Give the array's slots in a different order from Table 2-1 to prove the map decides.
  engine::TestSignals written = test_support::MakeSignals(array, 300, 2e-4, 0.01, true);
  const std::vector<std::filesystem::path> files = WriteNapTest(dir, written, UdsNumberForm::kSun, &map);
  engine::ArrayGeometry shuffled = array;
  std::reverse(shuffled.sensors.begin(), shuffled.sensors.end());
  const engine::TestSignals read = ReadUdsTest(files, shuffled, &map, "v0001");
  for (int i = 0; i < 9; ++i) {
    EXPECT_EQ(read.slots[i], written.slots[8 - i]);
    EXPECT_TRUE((read.samples.col(i).array() == written.samples.col(8 - i).array()).all());
  }
  EXPECT_DOUBLE_EQ(read.t0_s, 0.01);
}

}  // namespace
}  // namespace napkin::formats
