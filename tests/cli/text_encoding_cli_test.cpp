// Issue 19 item 7: one name that is not UTF-8 broke every JSON answer. A
// file named "M\xfcller.csv" (ISO-8859-1) or `--variant $'bad\xff'` was
// imported, and afterwards every `query ... --format json` and `compare
// --format json` failed with "internal error: [json.exception.type_error.316]
// invalid UTF-8 byte". Text entering the catalogue is UTF-8: header text of
// a known encoding (UDS-1992, ISO-MME: ISO-8859-1) is converted, names of an
// unknown one (file names, command-line names) are refused in one sentence;
// and output never fails on text an older napkin stored (docs/formats.md
// "Names, limits and escaping").
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "db/job_queue.h"
#include "formats/channel_map.h"
#include "formats/csv.h"
#include "formats/uds1992.h"
#include "records/config_record.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"

namespace napkin {
namespace {

namespace fs = std::filesystem;
using test_support::CommandResult;
using test_support::ExpectOneSentenceError;

// Strict UTF-8 (RFC 3629: no overlong forms, no surrogates, at most U+10FFFF),
// written out here so that the test does not trust the code it tests.
bool IsUtf8(const std::string& text) {
  std::size_t i = 0;
  while (i < text.size()) {
    const auto c = static_cast<unsigned char>(text[i]);
    std::size_t length = 0;
    unsigned low = 0x80;
    unsigned high = 0xBF;
    if (c < 0x80) {
      ++i;
      continue;
    }
    if (c >= 0xC2 && c <= 0xDF) {
      length = 2;
    } else if (c >= 0xE0 && c <= 0xEF) {
      length = 3;
      if (c == 0xE0) low = 0xA0;
      if (c == 0xED) high = 0x9F;
    } else if (c >= 0xF0 && c <= 0xF4) {
      length = 4;
      if (c == 0xF0) low = 0x90;
      if (c == 0xF4) high = 0x8F;
    } else {
      return false;
    }
    if (i + length > text.size()) return false;
    const auto second = static_cast<unsigned char>(text[i + 1]);
    if (second < low || second > high) return false;
    for (std::size_t k = 2; k < length; ++k)
      if ((static_cast<unsigned char>(text[i + k]) & 0xC0) != 0x80) return false;
    i += length;
  }
  return true;
}

class TextEncodingCli : public ::testing::Test {
 protected:
  CommandResult Napkin(const std::vector<std::string>& args) {
    return test_support::RunNapkin(dir_.path(), args);
  }

  CommandResult Import(std::vector<std::string> args) {
    args.insert(args.begin(), {"--db", "t.db", "import", "--array", "denton-3222", "--series", "enc"});
    return Napkin(args);
  }

  // `query tests --format json`: exit 0, valid UTF-8, parsed.
  nlohmann::json QueryTestsJson() {
    const CommandResult query = Napkin({"--db", "t.db", "query", "tests", "--format", "json"});
    EXPECT_EQ(query.exit_code, 0) << query.err;
    EXPECT_TRUE(IsUtf8(query.out)) << query.out;
    return query.exit_code == 0 ? nlohmann::json::parse(query.out) : nlohmann::json::array();
  }

  test_support::TempDir dir_;
};

TEST_F(TextEncodingCli, AFileNameThatIsNotUtf8IsRefusedNamingItAndJsonAnswersKeepWorking) {
  fs::create_directories(dir_ / "in");
  formats::WriteSignalsCsv(test_support::SynthNapTest(1).signals, dir_ / "in" / "good.csv");
  formats::WriteSignalsCsv(test_support::SynthNapTest(2).signals, dir_ / "in" / "M\xfcller.csv");

  const CommandResult imported = Import({"in"});
  EXPECT_EQ(imported.exit_code, 3) << imported.out << imported.err;  // one imported, one failed
  // One sentence naming the file, its bytes shown escaped (never raw on the terminal).
  ExpectOneSentenceError(imported, {"M\\xfcller.csv", "not valid UTF-8"});
  EXPECT_TRUE(IsUtf8(imported.err)) << imported.err;

  const nlohmann::json tests = QueryTestsJson();
  ASSERT_EQ(tests.size(), 1u) << tests.dump();
  EXPECT_EQ(tests[0].at("test_id"), "good");
}

TEST_F(TextEncodingCli, ANameOptionThatIsNotUtf8IsAUsageErrorNamingTheOption) {
  formats::WriteSignalsCsv(test_support::SynthNapTest(3).signals, dir_ / "a.csv");
  for (const auto& [option, value] : std::vector<std::pair<std::string, std::string>>{
           {"--variant", "bad\xff"}, {"--series", "s\xe9rie"}, {"--test-id", "t\xc3"}}) {
    const CommandResult refused =
        Napkin({"--db", "t.db", "import", "--array", "denton-3222", option, value, "a.csv"});
    EXPECT_EQ(refused.exit_code, 2) << option << ": " << refused.out;
    ExpectOneSentenceError(refused, {option, "not valid UTF-8"});
    EXPECT_TRUE(IsUtf8(refused.err)) << refused.err;
  }
  EXPECT_TRUE(QueryTestsJson().empty());
}

// UDS-1992 header text is ASCII or ISO-8859-1 in practice: converted to
// UTF-8. On main the Latin-1 TITLE failed the import ("could not be read
// ([json.exception.type_error.316] ...)").
TEST_F(TextEncodingCli, Latin1UdsHeaderTextIsStoredAsUtf8) {
  const engine::TestSignals signals = test_support::SynthNapTest(4).signals;
  const formats::ChannelMap map = formats::LoadChannelMap("nap-example");
  fs::create_directories(dir_ / "uds");
  for (int c = 0; c < 9; ++c) {
    formats::UdsChannel channel;
    channel.test_number = 7;
    channel.title =
        "Pr\xfc"
        "fung K\xf6ln";  // "Prüfung Köln" in ISO-8859-1
    channel.test_source = "Labor M\xfcller";
    const std::string& slot = signals.slots[static_cast<std::size_t>(c)];
    channel.curve_name = slot;
    channel.senatt = map.Find(slot)->senatt;
    channel.axis = map.Find(slot)->axis;
    channel.nfp = static_cast<int>(std::lround(signals.t0_s / signals.dt_s));
    channel.del_s = signals.dt_s;
    channel.values.assign(signals.samples.col(c).data(), signals.samples.col(c).data() + signals.size());
    formats::WriteUds1992(channel, dir_ / "uds" / ("k0007.00" + std::to_string(c + 1)));
  }
  const CommandResult imported = Import({"--channel-map", "nap-example", "uds"});
  ASSERT_EQ(imported.exit_code, 0) << imported.err;
  const nlohmann::json tests = QueryTestsJson();
  ASSERT_EQ(tests.size(), 1u);
  EXPECT_EQ(tests[0].at("title"),
            "Pr\xc3\xbc"
            "fung K\xc3\xb6ln");
  EXPECT_EQ(tests[0].at("laboratory"), "Labor M\xc3\xbcller");
}

// A catalogue an older napkin wrote may hold names that are not UTF-8: the
// JSON answers replace the bad bytes by U+FFFD instead of failing, tables
// show them escaped.
TEST_F(TextEncodingCli, StoredTextThatIsNotUtf8NeverBreaksAnAnswer) {
  {
    db::Catalogue catalogue = db::Catalogue::Open((dir_ / "t.db").string());
    const db::ArrayId array = catalogue.WriteArray(
        {{}, "ideal-3222", R"({"name":"ideal-3222","length_unit":"in","sensors":[]})", "array-hash-ideal"});
    const records::ResolvedConfig config = records::ResolveConfig("");
    const db::ConfigId config_id = catalogue.WriteConfig(config.record);
    int index = 0;
    for (const char* variant : {"v\xfe", "v\xfe", "w", "w"}) {
      db::TestRow test;
      test.external_id = "M\xfcller-" + std::to_string(index);
      test.series = "s\xff";
      test.variant = variant;
      test.array_id = array;
      test.source_path = "/data/M\xfcller-" + std::to_string(index) + ".csv";
      test.content_hash = "content-" + std::to_string(index);
      const db::TestId key = catalogue.WriteTest(test);
      engine::TestSummary summary;
      summary.hic15.value = 500.0 + 10.0 * index * index;
      if (index < 3) catalogue.WriteResult(key, config_id, summary, "exact");
      ++index;
    }
    // The last test failed with a message quoting its name.
    db::JobQueue queue(catalogue);
    queue.EnqueueMissing(config_id);
    const std::vector<db::Job> jobs = queue.ClaimJobs(config_id, "owner", 10, 60.0);
    ASSERT_EQ(jobs.size(), 1u);
    ASSERT_TRUE(queue.FailJob(jobs.front().id, "owner", "test 'M\xfcller-3' could not be read"));
  }
  const std::string replaced = "M\xef\xbf\xbdller-0";  // U+FFFD for the byte 0xfc
  const nlohmann::json tests = QueryTestsJson();
  ASSERT_EQ(tests.size(), 4u);
  EXPECT_EQ(tests[0].at("test_id"), replaced);
  EXPECT_EQ(tests[0].at("series"), "s\xef\xbf\xbd");

  const CommandResult hic = Napkin({"--db", "t.db", "query", "hic", "--format", "json"});
  EXPECT_EQ(hic.exit_code, 0) << hic.err;
  EXPECT_TRUE(IsUtf8(hic.out));
  const nlohmann::json hic_rows = hic.exit_code == 0 ? nlohmann::json::parse(hic.out) : nlohmann::json();
  EXPECT_EQ(hic_rows.size(), 3u) << hic.out;  // the tests with a result

  const CommandResult compare =
      Napkin({"--db", "t.db", "compare", "--series", "s\xff", "--metrics", "hic15", "--format", "json"});
  EXPECT_EQ(compare.exit_code, 0) << compare.err;
  EXPECT_TRUE(IsUtf8(compare.out));
  const nlohmann::json rows = compare.exit_code == 0 ? nlohmann::json::parse(compare.out) : nlohmann::json();
  ASSERT_EQ(rows.size(), 2u) << compare.out;
  EXPECT_EQ(rows[0].at("group"), "v\xef\xbf\xbd");

  const CommandResult status = Napkin({"--db", "t.db", "status", "--format", "json"});
  EXPECT_EQ(status.exit_code, 0) << status.err;
  EXPECT_TRUE(IsUtf8(status.out));
  const nlohmann::json counts = status.exit_code == 0 ? nlohmann::json::parse(status.out) : nlohmann::json();
  ASSERT_EQ(counts.at("failures").size(), 1u) << status.out;
  EXPECT_EQ(counts.at("failures")[0].at("error"), "test 'M\xef\xbf\xbdller-3' could not be read");

  // Tables and CSV show the byte escaped: the output is UTF-8 too.
  for (const char* format : {"table", "csv"}) {
    const CommandResult table = Napkin({"--db", "t.db", "query", "tests", "--format", format});
    EXPECT_EQ(table.exit_code, 0) << table.err;
    EXPECT_TRUE(IsUtf8(table.out)) << table.out;
    EXPECT_NE(table.out.find("M\\xfcller-0"), std::string::npos) << table.out;
  }
}

}  // namespace
}  // namespace napkin
