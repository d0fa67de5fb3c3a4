// DTS SLICEWare CSV exports (formats/dts_slice_csv.h, docs/formats.md "DTS
// SLICEWare CSV"): what is read from each row, and every refusal as one
// sentence naming the file, the row and the channel.
#include "formats/dts_slice_csv.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "common/error.h"
#include "engine/cfc_filter.h"
#include "formats/array_json.h"
#include "tests/formats/formats_test_util.h"
#include "tests/support/dts_slice_writer.h"
#include "tests/support/test_support.h"

namespace napkin::test_support {
namespace {

namespace fs = std::filesystem;

// Where the first data row starts: after the column row "Time,Chan 0:...".
std::size_t FirstDataRow(const std::string& text) {
  return text.find("\r\n", text.find("\r\nTime,") + 2) + 2;
}

class DtsSliceCsvTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const engine::ArrayGeometry array = formats::LoadArray("6aw-cg");
    signals_ = MakeSignals(array, 40, 1.0 / 20000.0, -0.0005);
    dts_ = SixDxExport(signals_, array);
  }

  fs::path Write(const std::string& text, const std::string& name = "export.csv") {
    const fs::path path = dir_ / name;
    WriteBytes(path, text);
    return path;
  }
  fs::path Write(const DtsExport& dts) { return Write(DtsExportText(dts)); }

  // The export's text with the first `row` line (its first cell) replaced by `replacement`.
  std::string WithRow(const std::string& row, const std::string& replacement) const {
    std::string text = DtsExportText(dts_);
    const std::size_t start = text.find(row + ",");
    const std::size_t end = text.find("\r\n", start);
    return text.replace(start, end - start, replacement);
  }

  // Reading `path` is refused in one sentence holding every fragment.
  static void ExpectRefused(const fs::path& path, std::initializer_list<std::string> fragments) {
    try {
      formats::ReadDtsSliceCsv(path);
      ADD_FAILURE() << "accepted " << path;
    } catch (const InputError& error) {
      const std::string what = error.what();
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
      EXPECT_TRUE(what.ends_with(".")) << what;
      EXPECT_EQ(what.rfind(path.string(), 0), 0u) << what;  // it names the file first
      for (const std::string& fragment : fragments)
        EXPECT_NE(what.find(fragment), std::string::npos) << what << "\nmissing: " << fragment;
    }
  }

  TempDir dir_;
  engine::TestSignals signals_;
  DtsExport dts_;
};

TEST_F(DtsSliceCsvTest, ReadsEveryChannelWithItsCodeUnitSamplingAndSensor) {
  const formats::DtsSliceExport read = formats::ReadDtsSliceCsv(Write(dts_));
  EXPECT_EQ(read.test_id, "DTS-1");
  EXPECT_EQ(read.info.test_number, "DTS-1");
  EXPECT_EQ(read.info.title, "synthetic head impact");
  EXPECT_EQ(read.info.date, "2024-05-23 10:42:07");
  ASSERT_EQ(read.channels.size(), 6u);
  for (std::size_t c = 0; c < 6; ++c) {
    const formats::RawChannel& channel = read.channels[c];
    SCOPED_TRACE(channel.code);
    EXPECT_EQ(channel.code, dts_.channels[c].code);
    EXPECT_EQ(channel.position, "D0");
    EXPECT_EQ(channel.unit, c < 3 ? "deg/sec" : "g");  // the trailing blank trimmed
    EXPECT_EQ(channel.serial, dts_.channels[c].serial);
    EXPECT_EQ(channel.hardware_filter, "4300");
    EXPECT_FALSE(channel.prefiltered_cfc);  // "None", whatever the code's filter letter (A, C)
    EXPECT_EQ(channel.dt_s, 1.0 / 20000.0);
    EXPECT_EQ(channel.t0_s, -0.0005);
    ASSERT_EQ(channel.values.size(), 40u);
    for (std::size_t k = 0; k < 40; ++k) EXPECT_EQ(channel.values[k], dts_.channels[c].values[k]);
  }
}

TEST_F(DtsSliceCsvTest, LineEndingsTrailingCommasAndByteOrderMarkDoNotMatter) {
  const formats::DtsSliceExport crlf = formats::ReadDtsSliceCsv(Write(dts_));
  DtsExport lf = dts_;
  lf.crlf = false;
  std::string text = DtsExportText(lf);
  // Without the trailing commas, and with a UTF-8 byte order mark.
  for (std::size_t at; (at = text.find(",\n")) != std::string::npos;) text.erase(at, 1);
  const formats::DtsSliceExport bare = formats::ReadDtsSliceCsv(Write("\xEF\xBB\xBF" + text, "lf.csv"));
  ASSERT_EQ(bare.channels.size(), crlf.channels.size());
  for (std::size_t c = 0; c < crlf.channels.size(); ++c) {
    EXPECT_EQ(bare.channels[c].code, crlf.channels[c].code);
    EXPECT_EQ(bare.channels[c].unit, crlf.channels[c].unit);
    EXPECT_EQ(bare.channels[c].values, crlf.channels[c].values);
  }
  EXPECT_EQ(bare.test_id, "DTS-1");
}

TEST_F(DtsSliceCsvTest, SoftwareFilterClassMarksTheChannelPrefiltered) {
  dts_.channels[0].software_filter = "60";
  dts_.channels[3].software_filter = "1000";
  dts_.channels[4].software_filter = "0";
  const formats::DtsSliceExport read = formats::ReadDtsSliceCsv(Write(dts_));
  EXPECT_EQ(read.channels[0].prefiltered_cfc, engine::kCfc60);
  EXPECT_EQ(read.channels[3].prefiltered_cfc, engine::kCfc1000);
  EXPECT_FALSE(read.channels[4].prefiltered_cfc);  // 0: no filter
  EXPECT_FALSE(read.channels[5].prefiltered_cfc);  // None, though its code's letter says A (CFC 1000)
}

TEST_F(DtsSliceCsvTest, TellsAnExportFromOtherCsvFiles) {
  EXPECT_TRUE(formats::LooksLikeDtsSliceCsv(DtsExportText(dts_).substr(0, 100)));
  EXPECT_TRUE(formats::LooksLikeDtsSliceCsv("\xEF\xBB\xBF\"Headers\",,\r\n"));
  EXPECT_FALSE(formats::LooksLikeDtsSliceCsv("time_s,cg_x\n0,1\n"));
  EXPECT_FALSE(formats::LooksLikeDtsSliceCsv("HeadersX,1\n"));
  EXPECT_FALSE(formats::LooksLikeDtsSliceCsv(""));
}

// Issue 46 (3): a header row with fewer values than channels.
TEST_F(DtsSliceCsvTest, ChannelRowWithFewerValuesThanChannelsIsRefused) {
  const fs::path path =
      Write(WithRow("Engineering Unit", "Engineering Unit,deg/sec ,deg/sec ,deg/sec ,g ,g "));
  ExpectRefused(path, {"row 15 (\"Engineering Unit\")", "has 5 values for 6 channels",
                       "channel \"Chan 5:6DX0855-AC1\" has none"});
}

// Issue 46 (3): a unit napkin does not know.
TEST_F(DtsSliceCsvTest, UnknownUnitOfAHeadChannelIsRefused) {
  dts_.channels[2].unit = "furlong/fortnight ";
  ExpectRefused(Write(dts_),
                {"row 15 (\"Engineering Unit\")", "channel \"Chan 2:6DX0855-AV1\" (D0HEADCG0000AVXC)",
                 "unrecognised unit \"furlong/fortnight\""});
  // Another sensor's unit is its own business: napkin reads no slot from it.
  dts_.channels[2].unit = "deg/sec ";
  DtsChannel load_cell;
  load_cell.code = "D0NECKUP0000FOZA";
  load_cell.unit = "N ";
  load_cell.values = dts_.channels[0].values;
  dts_.channels.push_back(load_cell);
  EXPECT_EQ(formats::ReadDtsSliceCsv(Write(dts_)).channels.size(), 7u);
}

// Issue 46 (3): a code that maps to no slot (a head channel along no body axis).
TEST_F(DtsSliceCsvTest, HeadChannelCodeAlongNoBodyAxisIsRefused) {
  dts_.channels[4].code = "D0HEADCG0000ACRA";
  ExpectRefused(Write(dts_),
                {"row 9 (\"ISO Channel Code\")", "channel \"Chan 4:6DX0855-AC2\" (D0HEADCG0000ACRA)",
                 "direction \"R\" is no body axis", "maps to no slot"});
}

// Issue 46 (3): a time column that disagrees with the sample rate.
TEST_F(DtsSliceCsvTest, TimeColumnDisagreeingWithTheRateIsRefused) {
  dts_.sample_rate_hz = 10000.0;  // the times step at 10 kHz
  std::string text = DtsExportText(dts_);
  const std::string rate_row = "Sample Rate (Hz),10000,10000,10000,10000,10000,10000,";
  text.replace(text.find(rate_row), rate_row.size(), "Sample Rate (Hz),20000,20000,20000,20000,20000,20000,");
  ExpectRefused(Write(text), {"row 25", "the time -0.0004 s disagrees with the sample rate 20000 Hz (row 6)",
                              "at -0.00045 s"});
}

TEST_F(DtsSliceCsvTest, TimesRoundedAsWrittenAreAccepted) {
  // 30 kHz written to the microsecond: each time off the rate's grid by up to a sixtieth of a sample.
  dts_.sample_rate_hz = 30000.0;
  dts_.t0_s = 0.0;
  std::string text = DtsExportText(dts_);
  std::string rounded;
  std::size_t line_start = 0;
  const std::size_t data = FirstDataRow(text);
  rounded = text.substr(0, data);
  for (line_start = data; line_start < text.size();) {
    const std::size_t comma = text.find(',', line_start);
    const std::size_t end = text.find("\r\n", line_start) + 2;
    char time[32];
    std::snprintf(time, sizeof(time), "%.6f", std::stod(text.substr(line_start, comma - line_start)));
    rounded += time + text.substr(comma, end - comma);
    line_start = end;
  }
  const formats::DtsSliceExport read = formats::ReadDtsSliceCsv(Write(rounded));
  EXPECT_EQ(read.channels.front().dt_s, 1.0 / 30000.0);
}

TEST_F(DtsSliceCsvTest, ChannelsOfDifferentRatesAreRefused) {
  const fs::path path =
      Write(WithRow("Sample Rate (Hz)", "Sample Rate (Hz),20000,20000,10000,20000,20000,20000,"));
  ExpectRefused(path, {"row 6 (\"Sample Rate (Hz)\")", "channel \"Chan 2:6DX0855-AV1\"",
                       "sampled at 10000 Hz", "one sample rate"});
}

TEST_F(DtsSliceCsvTest, SoftwareFilterThatIsNoClassIsRefused) {
  dts_.channels[1].software_filter = "Butterworth";
  ExpectRefused(Write(dts_), {"row 13 (\"Software Filter (SAE Class)\")", "channel \"Chan 1:6DX0855-AV2\"",
                              "\"Butterworth\" is no SAE filter class"});
}

TEST_F(DtsSliceCsvTest, BadDataRowsAreRefusedNamingRowAndChannel) {
  std::string text = DtsExportText(dts_);
  const std::size_t data = FirstDataRow(text);  // the first data row: line 24
  const std::size_t end = text.find("\r\n", data);
  const std::string first = text.substr(data, end - data);
  std::string short_row = first.substr(0, first.rfind(',', first.size() - 2) + 1);
  ExpectRefused(Write(std::string(text).replace(data, end - data, short_row)),
                {"row 24 has 5 values after the time for 6 channels",
                 "channel \"Chan 5:6DX0855-AC1\" (D0HEADCG0000ACXA) has none"});
  std::string bad = first;
  bad.replace(bad.find(',') + 1, bad.find(',', bad.find(',') + 1) - bad.find(',') - 1, "12.5g");
  ExpectRefused(Write(std::string(text).replace(data, end - data, bad)),
                {"row 24, channel \"Chan 0:6DX0855-AV3\"", "\"12.5g\" is not a number"});
  std::string nan = first;
  nan.replace(nan.find(',') + 1, nan.find(',', nan.find(',') + 1) - nan.find(',') - 1, "nan");
  ExpectRefused(Write(std::string(text).replace(data, end - data, nan)),
                {"row 24, channel \"Chan 0:6DX0855-AV3\"", "\"nan\" is not a finite number"});
}

TEST_F(DtsSliceCsvTest, MissingRowsAreRefused) {
  std::string text = DtsExportText(dts_);
  ExpectRefused(Write(text.substr(0, text.find("Data Starts Here"))), {"no row \"Data Starts Here\""});
  ExpectRefused(Write(WithRow("ISO Channel Code", "ISO Codes,a,b,c,d,e,f,")),
                {"no row \"ISO Channel Code\""});
  ExpectRefused(Write(text.substr(0, FirstDataRow(text))), {"has 0 data rows"});
}

}  // namespace
}  // namespace napkin::test_support
