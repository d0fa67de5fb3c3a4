// The input-format table (ingest/input_formats.h) and what follows from it:
// which format a file is, the files a test spans, zip members, and the array
// a test's channel codes define (ingest/array_from_codes.h).
#include "ingest/input_formats.h"

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <string>

#include "common/error.h"
#include "formats/array_json.h"
#include "formats/channel_map.h"
#include "formats/csv.h"
#include "ingest/array_from_codes.h"
#include "ingest/discovery.h"
#include "ingest/dummy_heads.h"
#include "tests/formats/formats_test_util.h"
#include "tests/support/dts_slice_writer.h"
#include "tests/support/test_support.h"

namespace napkin::ingest {
namespace {

namespace fs = std::filesystem;
using test_support::DtsExport;
using test_support::TempDir;

TEST(InputFormatTable, EveryFormatHasItsOwnNameAndWhatItsKindNeeds) {
  std::set<std::string_view> names;
  for (const InputFormatEntry& entry : InputFormats()) {
    SCOPED_TRACE(std::string(entry.name));
    EXPECT_TRUE(names.insert(entry.name).second);
    EXPECT_EQ(&FormatEntry(entry.format), &entry);
    EXPECT_FALSE(entry.title.empty());
    EXPECT_FALSE(entry.kind.empty());
    EXPECT_FALSE(entry.what.empty());
    EXPECT_NE(entry.names_test, nullptr);
    EXPECT_NE(entry.is_part, nullptr);
    // A channel reader exactly where the channels are mapped to slots.
    EXPECT_EQ(entry.read_channels != nullptr, entry.reader_kind == ReaderKind::kChannels);
  }
  // The names stored in metadata_json "format" (docs/formats.md): existing catalogues hold them.
  EXPECT_STREQ(InputFormatName(InputFormat::kCsv), "csv");
  EXPECT_STREQ(InputFormatName(InputFormat::kIsoMme), "iso-mme");
  EXPECT_STREQ(InputFormatName(InputFormat::kUds1992), "uds-1992");
  EXPECT_STREQ(InputFormatName(InputFormat::kZipArchive), "zip");
  EXPECT_STREQ(InputFormatName(InputFormat::kDtsSliceCsv), "dts-slice-csv");
  EXPECT_EQ(FormatList("or"),
            "DTS SLICEWare CSV exports, CSV files, ISO-MME test folders, UDS-1992 channel "
            "files or zip archives");
}

TEST(InputFormatTable, AFileIsTheFormatItsNameAndFirstBytesSay) {
  TempDir dir;
  const engine::ArrayGeometry array = formats::LoadArray("6aw-cg");
  const engine::TestSignals signals = test_support::MakeSignals(array, 8, 5e-5, 0.0);
  test_support::WriteDtsExport(test_support::SixDxExport(signals, array), dir / "export.csv");
  formats::WriteSignalsCsv(signals, dir / "plain.csv");
  test_support::WriteBytes(dir / "v1.001", "x");
  test_support::WriteBytes(dir / "T.mme", "x");
  test_support::WriteBytes(dir / "notes.txt", "x");
  EXPECT_EQ(FormatOfFile(dir / "export.csv"), InputFormat::kDtsSliceCsv);
  EXPECT_EQ(FormatOfFile(dir / "plain.csv"), InputFormat::kCsv);
  EXPECT_EQ(FormatOfFile(dir / "v1.001"), InputFormat::kUds1992);
  EXPECT_EQ(FormatOfFile(dir / "T.mme"), InputFormat::kIsoMme);
  EXPECT_EQ(FormatOfFile(dir / "notes.txt"), std::nullopt);
  EXPECT_EQ(FormatOfFolder(dir.path()), InputFormat::kIsoMme);  // it holds T.mme
  // Zip members: the files some format's tests are made of.
  for (const char* part : {"a.csv", "T.mme", "Channel/T.chn", "T.001"}) EXPECT_TRUE(IsTestPart(part)) << part;
  for (const char* other : {"report.pdf", "inner.zip", "photo.jpg"}) EXPECT_FALSE(IsTestPart(other)) << other;

  // Discovery: the export among napkin's CSV files, each a test of its own format.
  fs::create_directories(dir / "tree");
  fs::copy_file(dir / "export.csv", dir / "tree" / "a-export.csv");
  fs::copy_file(dir / "plain.csv", dir / "tree" / "b-plain.csv");
  const Discovery found = DiscoverInputs({(dir / "tree").string()});
  ASSERT_EQ(found.inputs.size(), 2u);
  EXPECT_EQ(found.inputs[0].format, InputFormat::kDtsSliceCsv);
  EXPECT_EQ(found.inputs[1].format, InputFormat::kCsv);
  EXPECT_EQ(FilesOf(found.inputs[0]), std::vector<fs::path>{dir / "tree" / "a-export.csv"});
}

// The head channels of one dummy: `codes` at position D0.
std::vector<formats::RawChannel> Channels(std::initializer_list<const char*> codes) {
  std::vector<formats::RawChannel> channels;
  for (const char* code : codes) {
    formats::RawChannel channel;
    channel.code = code;
    channel.position = channel.code.substr(0, 2);
    channel.source = "export.csv";
    channels.push_back(channel);
  }
  return channels;
}

void ExpectNoArray(const std::vector<formats::RawChannel>& channels,
                   std::initializer_list<std::string> fragments) {
  try {
    const std::string preset = ArrayPresetFromCodes(channels, "T1", "--array");
    ADD_FAILURE() << "the codes gave array " << preset;
  } catch (const InputError& error) {
    const std::string what = error.what();
    EXPECT_EQ(what.rfind("test T1: ", 0), 0u) << what;
    EXPECT_NE(what.find("--array"), std::string::npos) << what;
    for (const std::string& fragment : fragments) EXPECT_NE(what.find(fragment), std::string::npos) << what;
  }
}

TEST(ArrayFromCodes, HeadCgChannelsDefineTheirPreset) {
  // The 6DX headform: angular rates and accelerations at the head CG, whatever else is recorded.
  EXPECT_EQ(ArrayPresetFromCodes(
                Channels({"D0HEADCG0000AVZC", "D0HEADCG0000AVYC", "D0HEADCG0000AVXC", "D0HEADCG0000ACZA",
                          "D0HEADCG0000ACYA", "D0HEADCG0000ACXA", "D0NECKUP0000FOZA", "D0CHST0000H3ACXA"}),
                "T1", "--array"),
            "6aw-cg");
  // Accelerometers alone (the Hybrid III head triaxial); fine location 0000 is the CG too.
  EXPECT_EQ(ArrayPresetFromCodes(Channels({"11HEAD0000H3ACXA", "11HEAD0000H3ACYA", "11HEAD0000H3ACZA"}), "T1",
                                 "--array"),
            "3a-cg");
}

TEST(ArrayFromCodes, ArraysWithArmsOrMissingAxesNeedTheArrayGiven) {
  // A 3-2-2-2 head: the arms sit where only the geometry says.
  ExpectNoArray(
      Channels({"D0HEADCG0000ACXA", "D0HEADCG0000ACYA", "D0HEADCG0000ACZA", "D0HEADRI0000ACZA"}),
      {"channel D0HEADRI0000ACZA", "off the CG", "an array with arms needs its geometry", "--channel-map"});
  ExpectNoArray(Channels({"D0HEADCG0000ACXA", "D0HEADCG0000ACYA"}), {"CG accelerometers along x and y"});
  ExpectNoArray(Channels({"D0HEADCG0000ACXA", "D0HEADCG0000ACYA", "D0HEADCG0000ACZA", "D0HEADCG0000AVXC"}),
                {"angular-rate sensors along x"});
  ExpectNoArray(Channels({"D0NECKUP0000FOZA"}), {"no channel code names a head accelerometer"});
  ExpectNoArray(Channels({"11HEADCG0000ACXA", "11HEADCG0000ACYA", "11HEADCG0000ACZA", "13HEADCG0000ACXA",
                          "13HEADCG0000ACYA", "13HEADCG0000ACZA", "13HEADCG0000AVXC", "13HEADCG0000AVYC",
                          "13HEADCG0000AVZC"}),
                {"position 11 is array 3a-cg", "position 13 array 6aw-cg"});
}

// Issue 46 (3): two channels on one slot, named with the export's file, row and column.
TEST(DtsSliceHeads, TwoChannelsOnOneSlotAreRefusedNamingBoth) {
  TempDir dir;
  const engine::ArrayGeometry array = formats::LoadArray("6aw-cg");
  DtsExport dts = test_support::SixDxExport(test_support::MakeSignals(array, 8, 5e-5, 0.0), array);
  dts.channels.push_back(dts.channels.front());  // a second AV Z sensor
  dts.channels.back().serial = "6DX0856-AV3";
  test_support::WriteDtsExport(dts, dir / "export.csv");
  const formats::ChannelMap map = formats::LoadChannelMap("default");
  HeadReadOptions options;
  options.default_map = &map;
  for (const engine::ArrayGeometry* given : {static_cast<const engine::ArrayGeometry*>(nullptr), &array}) {
    options.array = given;  // the array the codes define (6aw-cg), and the same given
    try {
      ReadInputHeads({InputFormat::kDtsSliceCsv, "export", dir / "export.csv", {}}, options, "export");
      ADD_FAILURE() << "accepted";
    } catch (const InputError& error) {
      const std::string what = error.what();
      const std::string file = (dir / "export.csv").string();
      for (const std::string& fragment :
           {std::string("test DTS-1: slot \"ars_z\" is matched by two channels"),
            "channel D0HEADCG0000AVZC (" + file + ": column \"Chan 0:6DX0855-AV3\", code in row 9)",
            "channel D0HEADCG0000AVZC (" + file + ": column \"Chan 6:6DX0856-AV3\", code in row 9)"})
        EXPECT_NE(what.find(fragment), std::string::npos) << what << "\nmissing: " << fragment;
    }
  }
}

}  // namespace
}  // namespace napkin::ingest
