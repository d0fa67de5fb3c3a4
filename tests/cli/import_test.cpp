// `napkin import` end to end: round trips through every input format,
// idempotence, one transaction per test (resumable folder imports), bad input
// refused with one sentence and the catalogue unchanged, and command-line
// strings kept out of SQL text.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>

#include "formats/channel_map.h"
#include "formats/csv.h"
#include "formats/isomme.h"
#include "formats/uds1992.h"
#include "ingest/content_hash.h"
#include "ingest/discovery.h"
#include "records/array_record.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"
#include "tests/support/zip_writer.h"

namespace napkin::cli {

using namespace napkin::test_support;
namespace {

using ingest::DiscoverInputs;
using ingest::Discovery;
using ingest::InputContentHash;
using ingest::InputFormat;

// Writes the nine NAP channels of `signals` as UDS-1992 files <folder>/<stem>.001
// ... .009 in Table 2-1 order, with SENATT/AXIS as the nap-example map names them.
void WriteUdsGroup(const engine::TestSignals& signals, const fs::path& folder, const std::string& stem,
                   formats::UdsNumberForm form, bool with_sensor_labels = true) {
  const formats::ChannelMap map = formats::LoadChannelMap("nap-example");
  fs::create_directories(folder);
  for (int c = 0; c < 9; ++c) {
    formats::UdsChannel channel;
    channel.number_form = form;
    channel.test_number = 1;
    channel.test_name = stem;
    channel.curve_name = signals.slots[static_cast<std::size_t>(c)];
    if (with_sensor_labels) {
      const formats::ChannelMapEntry* entry = map.Find(signals.slots[static_cast<std::size_t>(c)]);
      channel.senatt = entry->senatt;
      channel.axis = entry->axis;
    }
    channel.nfp = static_cast<int>(std::lround(signals.t0_s / signals.dt_s));
    channel.del_s = signals.dt_s;
    channel.values.assign(signals.samples.col(c).data(), signals.samples.col(c).data() + signals.size());
    char suffix[8];
    std::snprintf(suffix, sizeof suffix, ".%03d", c + 1);
    formats::WriteUds1992(channel, folder / (stem + suffix));
  }
}

Eigen::MatrixXd Float32Rounded(const Eigen::MatrixXd& samples) {
  return samples.cast<float>().cast<double>();
}

class CliImport : public ::testing::Test {
 protected:
  void SetUp() override {
    const RunResult init = RunNapkin(dir_.path(), {"init"});
    ASSERT_EQ(init.exit_code, 0) << init.err;
  }

  RunResult Import(std::vector<std::string> args) {
    args.insert(args.begin(), {"--db", "napkin.db", "import", "--array", "denton-3222"});
    return RunNapkin(dir_.path(), args);
  }

  engine::TestSignals SignalsOf(const std::string& test_id) {
    db::Catalogue catalogue = OpenForReading(db_path());
    const std::optional<db::TestId> key = catalogue.FindTestByExternalId(test_id);
    if (!key) {
      ADD_FAILURE() << "no test " << test_id;
      return {};
    }
    return catalogue.ReadTestSignals(*key);
  }

  std::vector<std::string> TestIds() {
    std::vector<std::string> ids;
    for (const db::TestRow& test : OpenForReading(db_path()).ReadAllTests()) ids.push_back(test.external_id);
    return ids;
  }

  fs::path db_path() const { return dir_ / "napkin.db"; }

  napkin::test_support::TempDir dir_;
};

// ------------------------------------------------------------ round trips

TEST_F(CliImport, EveryFormatImportsTheSameSamples) {
  const synth::SyntheticTest synth = SynthNapTest(11);
  const engine::TestSignals& truth = synth.signals;
  const fs::path tests = dir_ / "tests";
  fs::create_directories(tests);
  formats::WriteSignalsCsv(truth, tests / "c0001.csv");
  formats::WriteIsoMme(truth, synth.array, formats::LoadChannelMap("nap-example"), tests / "m0001", "M0001");
  WriteUdsGroup(truth, tests / "uds", "ieee", formats::UdsNumberForm::kIeee);
  WriteUdsGroup(truth, tests / "uds", "vax", formats::UdsNumberForm::kVax);
  WriteUdsGroup(truth, tests / "uds", "sun", formats::UdsNumberForm::kSun);

  const RunResult run = Import({"--series", "roundtrip", "--variant", "none", "--channel-map", "nap-example",
                                TripleFlag("--orientation", synth.initial.orientation_rad),
                                TripleFlag("--initial-velocity", synth.initial.velocity_fixed_mps), "tests"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.err, "");
  EXPECT_EQ(Lines(run.out).back(), "imported 5 tests, skipped 0 already present.");
  EXPECT_EQ(TestIds(), (std::vector<std::string>{"c0001", "ieee", "m0001", "sun", "vax"}));  // by id

  for (const char* id : {"c0001", "m0001"}) {
    const engine::TestSignals back = SignalsOf(id);
    EXPECT_EQ(back.slots, truth.slots) << id;
    EXPECT_EQ(back.dt_s, truth.dt_s) << id;
    EXPECT_EQ(back.t0_s, truth.t0_s) << id;
    EXPECT_EQ(back.samples, truth.samples) << id;  // bit-exact
  }
  // UDS-1992 stores REAL*4: the samples are the float32-rounded truth; DEL
  // reads back as the decimal its REAL*4 stands for (1e-4).
  for (const char* id : {"ieee", "vax", "sun"}) {
    const engine::TestSignals back = SignalsOf(id);
    EXPECT_EQ(back.slots, truth.slots) << id;
    EXPECT_EQ(back.dt_s, truth.dt_s) << id;
    EXPECT_EQ(back.samples, Float32Rounded(truth.samples)) << id;
  }

  db::Catalogue catalogue = OpenForReading(db_path());
  for (const db::TestRow& test : catalogue.ReadAllTests()) {
    EXPECT_EQ(test.series, "roundtrip");
    EXPECT_EQ(test.variant, "none");
    EXPECT_EQ(test.initial_state.orientation_rad,
              synth.initial.orientation_rad);  // exact through the text flag
    EXPECT_EQ(test.initial_state.velocity_fixed_mps, synth.initial.velocity_fixed_mps);
    // The stored array reads back as the preset, bit-exact.
    const db::ArrayRow array = catalogue.ReadArray(test.array_id);
    const engine::ArrayGeometry geometry = records::DecodeArrayRecord(array);
    ASSERT_EQ(geometry.sensors.size(), synth.array.sensors.size());
    for (std::size_t i = 0; i < geometry.sensors.size(); ++i) {
      EXPECT_EQ(geometry.sensors[i].position_body_m, synth.array.sensors[i].position_body_m);
      EXPECT_EQ(geometry.sensors[i].axis_body, synth.array.sensors[i].axis_body);
    }
    const std::vector<db::RawChannelInfo> info = catalogue.ReadRawChannelInfo(test.id);
    ASSERT_EQ(info.size(), 9u);
    EXPECT_EQ(info[0].unit, "g");
  }
  // One array row shared by the five tests.
  EXPECT_EQ(catalogue.Query(db::QueryKind::kTests).rows.size(), 5u);
}

TEST_F(CliImport, NineUdsFilesWithoutAMapFillTheTable21SlotsAndShareTheirStem) {
  const synth::SyntheticTest synth = SynthNapTest(12);
  WriteUdsGroup(synth.signals, dir_ / "raw", "v0001", formats::UdsNumberForm::kVax,
                /*with_sensor_labels=*/false);
  std::vector<std::string> args;
  for (int c = 9; c >= 1; --c)
    args.push_back("raw/v0001.00" + std::to_string(c));  // any order on the command line
  const RunResult run = Import(args);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(TestIds(), std::vector<std::string>{"v0001"});
  const engine::TestSignals back = SignalsOf("v0001");
  EXPECT_EQ(back.slots, synth.signals.slots);
  EXPECT_EQ(back.samples, Float32Rounded(synth.signals.samples));
}

TEST_F(CliImport, TestIdOptionNamesASingleTestAndIsAUsageErrorForSeveral) {
  const synth::SyntheticTest synth = SynthNapTest(13);
  formats::WriteSignalsCsv(synth.signals, dir_ / "a.csv");
  formats::WriteSignalsCsv(SynthNapTest(14).signals, dir_ / "b.csv");
  const RunResult one = Import({"--test-id", "sled-42", "a.csv"});
  ASSERT_EQ(one.exit_code, 0) << one.err;
  EXPECT_EQ(TestIds(), std::vector<std::string>{"sled-42"});

  const std::string dump = DumpCatalogue(db_path());
  const RunResult two = Import({"--test-id", "sled-43", "a.csv", "b.csv"});
  EXPECT_EQ(two.exit_code, 2);
  ExpectOneSentenceError(two, {"--test-id", "2"});
  EXPECT_EQ(DumpCatalogue(db_path()), dump);
}

// ------------------------------------------------------------ idempotence

TEST_F(CliImport, ImportingTheSameFileTwiceAddsNothingAndSaysSo) {
  formats::WriteSignalsCsv(SynthNapTest(21).signals, dir_ / "v0001.csv");
  const RunResult first = Import({"v0001.csv"});
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_EQ(first.out, "imported 1 test, skipped 0 already present.\n");
  const std::string dump = DumpCatalogue(db_path());

  const RunResult second = Import({"v0001.csv"});
  EXPECT_EQ(second.exit_code, 0) << second.err;
  EXPECT_EQ(second.out,
            "v0001: already imported (same content), skipped.\n"
            "imported 0 tests, skipped 1 already present.\n");
  EXPECT_EQ(second.err, "");
  EXPECT_EQ(DumpCatalogue(db_path()), dump);

  // The same content under another name is the same test, still skipped.
  fs::copy_file(dir_ / "v0001.csv", dir_ / "copy.csv");
  const RunResult copy = Import({"copy.csv"});
  EXPECT_EQ(copy.exit_code, 0);
  EXPECT_EQ(DumpCatalogue(db_path()), dump);

  // Other content under an existing id is refused, naming both sources.
  const RunResult clash = [&] {
    fs::create_directories(dir_ / "other");
    formats::WriteSignalsCsv(SynthNapTest(22).signals, dir_ / "other" / "v0001.csv");
    return Import({"other/v0001.csv"});
  }();
  EXPECT_EQ(clash.exit_code, 1);
  ExpectOneSentenceError(clash, {"'v0001'", "other/v0001.csv", "--test-id"});
  EXPECT_EQ(DumpCatalogue(db_path()), dump);
}

// ------------------------------------------------- folders: one transaction per test

constexpr int kFolderTests = 200;

std::string FolderTestName(int i) {
  char name[16];
  std::snprintf(name, sizeof name, "t%03d", i);
  return name;
}

// 200 small distinct tests (11 ms at 10 kHz).
std::map<std::string, engine::TestSignals> WriteFolderOfTests(const fs::path& folder) {
  fs::create_directories(folder);
  std::map<std::string, engine::TestSignals> written;
  synth::SyntheticTest base = SynthNapTest(31, 0.01);
  for (int i = 0; i < kFolderTests; ++i) {
    engine::TestSignals signals = base.signals;
    signals.samples.array() += 0.001 * i;
    formats::WriteSignalsCsv(signals, folder / (FolderTestName(i) + ".csv"));
    written.emplace(FolderTestName(i), std::move(signals));
  }
  return written;
}

TEST_F(CliImport, FolderWithABadTestInTheMiddleKeepsTheOthersAndARerunResumes) {
  const auto written = WriteFolderOfTests(dir_ / "series");
  const fs::path bad = dir_ / "series" / "t100.csv";
  const std::string good_text = ReadText(bad);
  std::string bad_text = good_text;
  const std::size_t row = bad_text.find('\n', bad_text.find("time_s")) + 1;  // first data row
  bad_text.replace(bad_text.find(',', row) + 1, 0, "x");                     // "x<number>" in column cg_x
  WriteText(bad, bad_text);

  const RunResult first = Import({"--series", "s", "series"});
  EXPECT_EQ(first.exit_code, 3) << first.err;  // partial success
  ExpectOneSentenceError(first, {"t100.csv", "cg_x"});
  EXPECT_EQ(Lines(first.out).back(), "imported 199 tests, skipped 0 already present, 1 failed.");
  std::vector<std::string> ids = TestIds();
  EXPECT_EQ(ids.size(), 199u);
  EXPECT_EQ(std::count(ids.begin(), ids.end(), "t100"), 0);

  WriteText(bad, good_text);
  const RunResult second = Import({"--series", "s", "series"});
  EXPECT_EQ(second.exit_code, 0) << second.err;
  EXPECT_EQ(Lines(second.out).back(), "imported 1 test, skipped 199 already present.");
  ids = TestIds();
  ASSERT_EQ(ids.size(), 200u);
  EXPECT_EQ(std::set<std::string>(ids.begin(), ids.end()).size(), 200u);
  EXPECT_EQ(SignalsOf("t100").samples, written.at("t100").samples);
}

TEST_F(CliImport, KilledFolderImportKeepsFinishedTestsWholeAndARerunCompletesIt) {
  const auto written = WriteFolderOfTests(dir_ / "series");
  const pid_t child = napkin::test_support::StartProgram(
      NAPKIN_BINARY, {"--db", "napkin.db", "import", "--array", "denton-3222", "series"}, "/dev/null",
      "/dev/null", dir_.path());
  ASSERT_GT(child, 0);
  // Kill it (SIGKILL: no cleanup at all) once some tests are committed.
  std::size_t seen = 0;
  for (int attempt = 0; attempt < 4000 && seen < 20; ++attempt) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    try {
      seen = OpenForReading(db_path()).ReadAllTests().size();
    } catch (const std::exception&) {
      // the writer may hold a lock for a moment
    }
  }
  kill(child, SIGKILL);
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_GT(seen, 0u) << "the import never committed a test";

  // Every committed test is whole: its nine channels with the file's samples.
  std::size_t kept = 0;
  {
    db::Catalogue catalogue = OpenForReading(db_path());
    for (const db::TestRow& test : catalogue.ReadAllTests()) {
      ++kept;
      EXPECT_EQ(catalogue.ReadTestSignals(test.id).samples, written.at(test.external_id).samples)
          << test.external_id;
    }
  }
  EXPECT_GE(kept, seen);
  RecordProperty("tests_kept_after_kill", static_cast<int>(kept));

  const RunResult rerun = Import({"series"});
  EXPECT_EQ(rerun.exit_code, 0) << rerun.err;
  EXPECT_EQ(Lines(rerun.out).back(), "imported " + std::to_string(kFolderTests - kept) + " tests, skipped " +
                                         std::to_string(kept) + " already present.")
      << "(killed after " << kept << " tests)";
  db::Catalogue catalogue = OpenForReading(db_path());
  const std::vector<db::TestRow> tests = catalogue.ReadAllTests();
  ASSERT_EQ(tests.size(), static_cast<std::size_t>(kFolderTests));
  std::set<std::string> ids;
  for (const db::TestRow& test : tests) {
    ids.insert(test.external_id);
    EXPECT_EQ(catalogue.ReadTestSignals(test.id).samples, written.at(test.external_id).samples);
  }
  EXPECT_EQ(ids.size(), static_cast<std::size_t>(kFolderTests));
}

// ------------------------------------------------------------ bad input

class CliImportBadInput : public CliImport {
 protected:
  void SetUp() override {
    CliImport::SetUp();
    // A catalogue that already holds a test, so "unchanged" is not trivially true.
    formats::WriteSignalsCsv(SynthNapTest(41).signals, dir_ / "good.csv");
    ASSERT_EQ(Import({"--series", "s", "good.csv"}).exit_code, 0);
    dump_ = DumpCatalogue(db_path());
  }

  // The import fails with exit 1, one sentence holding the fragments, and
  // leaves the catalogue exactly as it was.
  void ExpectRefused(const std::vector<std::string>& args, std::initializer_list<std::string> fragments) {
    const RunResult run = Import(args);
    EXPECT_EQ(run.exit_code, 1) << run.out;
    ExpectOneSentenceError(run, fragments);
    EXPECT_EQ(DumpCatalogue(db_path()), dump_);
  }

  void WriteIsoTest(const fs::path& folder) {
    const synth::SyntheticTest synth = SynthNapTest(42);
    formats::WriteIsoMme(synth.signals, synth.array, formats::LoadChannelMap("nap-example"), folder, "iso");
  }

  std::string dump_;
};

TEST_F(CliImportBadInput, TruncatedUdsRecord) {
  WriteUdsGroup(SynthNapTest(43).signals, dir_ / "uds", "v0002", formats::UdsNumberForm::kIeee);
  const fs::path file = dir_ / "uds" / "v0002.004";
  fs::resize_file(file, fs::file_size(file) - 100);
  ExpectRefused({"uds"}, {"v0002.004", "truncated"});
}

TEST_F(CliImportBadInput, WrongUdsFilever) {
  WriteUdsGroup(SynthNapTest(44).signals, dir_ / "uds", "v0003", formats::UdsNumberForm::kSun);
  const fs::path file = dir_ / "uds" / "v0003.007";
  std::string bytes = ReadText(file);
  ASSERT_EQ(bytes.substr(0, 8), "UDS-1992");
  bytes.replace(0, 8, "UDS-1991");
  WriteText(file, bytes);
  ExpectRefused({"--channel-map", "nap-example", "uds"}, {"v0003.007", "FILEVER"});
}

TEST_F(CliImportBadInput, IsoMmeChannelWithFewerSamplesThanDeclared) {
  WriteIsoTest(dir_ / "iso");
  const fs::path file = dir_ / "iso" / "Channel" / "iso.003";
  std::string text = ReadText(file);
  text.erase(text.rfind('\n', text.size() - 2) + 1);  // drop the last sample line
  WriteText(file, text);
  ExpectRefused({"--channel-map", "nap-example", "iso"}, {"iso.003", "declares"});
}

TEST_F(CliImportBadInput, IsoMmeMissingChannelFile) {
  WriteIsoTest(dir_ / "iso");
  fs::remove(dir_ / "iso" / "Channel" / "iso.005");
  ExpectRefused({"--channel-map", "nap-example", "iso"}, {"iso.005", "missing"});
}

TEST_F(CliImportBadInput, ChannelsWithDifferentSamplingIntervals) {
  WriteIsoTest(dir_ / "iso");
  const fs::path file = dir_ / "iso" / "Channel" / "iso.002";
  std::string text = ReadText(file);
  const std::size_t key = text.find("Sampling interval");
  ASSERT_NE(key, std::string::npos);
  const std::size_t colon = text.find(':', key);
  text.replace(colon + 1, text.find('\n', colon) - colon - 1, "0.0002");
  WriteText(file, text);
  ExpectRefused({"--channel-map", "nap-example", "iso"}, {"iso", "sampled every"});
}

TEST_F(CliImportBadInput, CsvWithANonNumericCell) {
  formats::WriteSignalsCsv(SynthNapTest(45).signals, dir_ / "bad.csv");
  std::string text = ReadText(dir_ / "bad.csv");
  const std::size_t row = text.find('\n', text.find("time_s")) + 1;
  const std::size_t third = text.find(',', text.find(',', row) + 1) + 1;  // column cg_y
  text.replace(third, text.find(',', third) - third, "n/a");
  WriteText(dir_ / "bad.csv", text);
  ExpectRefused({"bad.csv"}, {"bad.csv", "row", "cg_y"});
}

TEST_F(CliImportBadInput, PathThatDoesNotExist) {
  ExpectRefused({"nowhere.csv"}, {"nowhere.csv", "does not exist"});
}

TEST_F(CliImportBadInput, UnknownArrayPreset) {
  const RunResult run = RunNapkin(dir_.path(), {"import", "--array", "no-such-array", "good.csv"});
  EXPECT_EQ(run.exit_code, 2);  // a usage error, as every unknown preset (docs/formats.md "Presets")
  ExpectOneSentenceError(run, {"no-such-array"});
  EXPECT_EQ(DumpCatalogue(db_path()), dump_);
}

TEST_F(CliImportBadInput, CatalogueThatIsNotSqlite) {
  const std::string text = "this is a spreadsheet, not a catalogue\n";
  WriteText(dir_ / "sheet.db", text);
  const RunResult run =
      RunNapkin(dir_.path(), {"--db", "sheet.db", "import", "--array", "denton-3222", "good.csv"});
  EXPECT_EQ(run.exit_code, 1);
  ExpectOneSentenceError(run, {"sheet.db", "not a napkin catalogue"});
  EXPECT_EQ(ReadText(dir_ / "sheet.db"), text);
}

TEST_F(CliImportBadInput, ReadOnlyCatalogue) {
  formats::WriteSignalsCsv(SynthNapTest(46).signals, dir_ / "new.csv");
  ASSERT_EQ(chmod(db_path().c_str(), 0444), 0);
  const RunResult run = Import({"new.csv"});
  EXPECT_EQ(run.exit_code, 1);
  ExpectOneSentenceError(run, {"napkin.db", "read-only"});
  EXPECT_EQ(DumpCatalogue(db_path()), dump_);
  chmod(db_path().c_str(), 0644);
}

// ------------------------------------------------------------ SQL safety

TEST_F(CliImport, CommandLineStringsNeverReachSqlText) {
  const std::string series = "x'); DROP TABLE tests;--";
  const std::string variant = "\"; DELETE FROM series; --";
  formats::WriteSignalsCsv(SynthNapTest(51).signals, dir_ / "inj.csv");
  formats::WriteSignalsCsv(SynthNapTest(52).signals, dir_ / "plain.csv");
  ASSERT_EQ(Import({"--series", series, "--variant", variant, "inj.csv"}).exit_code, 0);
  ASSERT_EQ(Import({"--series", "plain", "plain.csv"}).exit_code, 0);

  const RunResult query = RunNapkin(dir_.path(), {"query", "tests", "--series", series, "--format", "json"});
  ASSERT_EQ(query.exit_code, 0) << query.err;
  const nlohmann::json rows = nlohmann::json::parse(query.out);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0]["test_id"], "inj");
  EXPECT_EQ(rows[0]["series"], series);
  EXPECT_EQ(rows[0]["variant"], variant);
  EXPECT_EQ(TestIds(), (std::vector<std::string>{"inj", "plain"}));
  db::Catalogue catalogue = OpenForReading(db_path());
  EXPECT_EQ(db::CatalogueInspector(catalogue).ReadAllSeries().size(), 2u);
}

// ------------------------------------------------------------ options

TEST_F(CliImport, TripleOptionsTakeOneArgumentWhereverTheyStand) {
  formats::WriteSignalsCsv(SynthNapTest(71).signals, dir_ / "o.csv");
  // A triple followed by the path and then by more options.
  const RunResult run =
      Import({"--orientation", "0.25,-0.5,1e-3", "o.csv", "--initial-velocity=-7,0,2.5", "--series", "s"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const db::TestRow test = OpenForReading(db_path()).ReadAllTests().at(0);
  EXPECT_EQ(test.initial_state.orientation_rad, Eigen::Vector3d(0.25, -0.5, 1e-3));
  EXPECT_EQ(test.initial_state.velocity_fixed_mps, Eigen::Vector3d(-7, 0, 2.5));
  EXPECT_EQ(test.series, "s");

  const std::string dump = DumpCatalogue(db_path());
  for (const char* bad : {"1,2", "1,2,3,4", "1,x,3", "1,,3", "nan,0,0"}) {
    const RunResult refused = Import({"--orientation", bad, "o2.csv"});
    EXPECT_EQ(refused.exit_code, 2) << bad;
    EXPECT_NE(refused.err.find("--orientation"), std::string::npos) << refused.err;
  }
  EXPECT_EQ(DumpCatalogue(db_path()), dump);
}

// ------------------------------------------------------------ discovery

TEST(ImportDiscovery, FindsEachKindOfTestInAFolderTree) {
  napkin::test_support::TempDir dir;
  const synth::SyntheticTest synth = SynthNapTest(61);
  fs::create_directories(dir / "tree" / "nested");
  formats::WriteSignalsCsv(synth.signals, dir / "tree" / "a.csv");
  formats::WriteIsoMme(synth.signals, synth.array, formats::LoadChannelMap("nap-example"),
                       dir / "tree" / "nested" / "iso1", "T1");
  WriteUdsGroup(synth.signals, dir / "tree" / "nested", "v0009", formats::UdsNumberForm::kIeee);
  WriteText(dir / "tree" / "README.txt", "notes\n");

  const Discovery found = DiscoverInputs({(dir / "tree").string() + "/", (dir / "missing").string()});
  ASSERT_EQ(found.inputs.size(), 3u);
  EXPECT_EQ(found.inputs[0].format, InputFormat::kCsv);
  EXPECT_EQ(found.inputs[0].name, "a");
  EXPECT_EQ(found.inputs[1].format, InputFormat::kIsoMme);
  EXPECT_EQ(found.inputs[1].name, "iso1");
  EXPECT_EQ(found.inputs[2].format, InputFormat::kUds1992);
  EXPECT_EQ(found.inputs[2].name, "v0009");
  ASSERT_EQ(found.inputs[2].files.size(), 9u);
  EXPECT_EQ(found.inputs[2].files.front().filename(), "v0009.001");
  EXPECT_EQ(found.inputs[2].files.back().filename(), "v0009.009");
  ASSERT_EQ(found.errors.size(), 1u);
  EXPECT_NE(found.errors[0].find("missing"), std::string::npos);

  // The .mme file itself names its folder's test.
  const Discovery mme = DiscoverInputs({(dir / "tree" / "nested" / "iso1" / "T1.mme").string()});
  ASSERT_EQ(mme.inputs.size(), 1u);
  EXPECT_EQ(mme.inputs[0].name, "T1");
  EXPECT_EQ(mme.inputs[0].source, dir / "tree" / "nested" / "iso1");

  // A link back up the tree is not followed twice.
  fs::create_directory_symlink(dir / "tree", dir / "tree" / "nested" / "loop");
  EXPECT_EQ(DiscoverInputs({(dir / "tree").string()}).inputs.size(), 3u);

  // An empty folder holds no test.
  fs::create_directories(dir / "empty");
  const Discovery none = DiscoverInputs({(dir / "empty").string()});
  EXPECT_TRUE(none.inputs.empty());
  ASSERT_EQ(none.errors.size(), 1u);
  EXPECT_NE(none.errors[0].find("holds no test"), std::string::npos);
}

TEST(ImportDiscovery, UdsGroupHashDependsOnEveryMemberFile) {
  napkin::test_support::TempDir dir;
  const synth::SyntheticTest synth = SynthNapTest(62);
  WriteUdsGroup(synth.signals, dir / "u", "v1", formats::UdsNumberForm::kIeee);
  const Discovery found = DiscoverInputs({(dir / "u").string()});
  ASSERT_EQ(found.inputs.size(), 1u);
  const std::string before = InputContentHash(found.inputs[0]);
  EXPECT_EQ(before.size(), 64u);
  std::string bytes = ReadText(dir / "u" / "v1.009");
  bytes.back() ^= 1;
  WriteText(dir / "u" / "v1.009", bytes);
  EXPECT_NE(InputContentHash(found.inputs[0]), before);
}

// ------------------------------------------------------------ transform

// `napkin transform` reads every format `napkin import` reads (issue 43, point 3): the same
// samples as napkin's CSV, an ISO-MME folder, its .mme file, a UDS-1992 group and a zip archive of
// the ISO-MME test give the same derived channels, byte for byte.
TEST(TransformEveryFormat, EachFormatOfTheSameSamplesGivesTheSameOutput) {
  napkin::test_support::TempDir dir;
  synth::SyntheticTest synth = SynthNapTest(4301);
  synth.signals.samples = Float32Rounded(synth.signals.samples);  // what UDS-1992's REAL*4 holds
  formats::WriteSignalsCsv(synth.signals, dir / "t.csv");
  formats::WriteIsoMme(synth.signals, synth.array, formats::LoadChannelMap("nap-example"), dir / "iso", "T1");
  WriteUdsGroup(synth.signals, dir / "uds", "v0001", formats::UdsNumberForm::kIeee);
  napkin::test_support::WriteZip(dir / "iso.zip", napkin::test_support::FolderEntries(dir / "iso"));
  const auto transform = [&](const std::string& input, const std::string& out,
                             std::vector<std::string> extra) {
    std::vector<std::string> args = {"transform",
                                     input,
                                     "--array",
                                     "denton-3222",
                                     "--out",
                                     out,
                                     TripleFlag("--orientation", synth.initial.orientation_rad)};
    args.insert(args.end(), extra.begin(), extra.end());
    const RunResult result = RunNapkin(dir.path(), args);
    EXPECT_EQ(result.exit_code, 0) << input << ": " << result.err;
    return ReadText(dir / out);
  };
  const std::string csv = transform("t.csv", "csv.out", {});
  ASSERT_FALSE(csv.empty());
  EXPECT_EQ(transform("iso", "iso.out", {"--channel-map", "nap-example"}), csv);
  EXPECT_EQ(transform("iso/T1.mme", "mme.out", {"--channel-map", "nap-example"}), csv);
  EXPECT_EQ(transform("uds", "uds.out", {}), csv);  // nine files in Table 2-1 order, no map
  EXPECT_EQ(transform("iso.zip", "zip.out", {"--channel-map", "nap-example"}), csv);
  // A folder of several tests is not one test.
  const RunResult several =
      RunNapkin(dir.path(), {"transform", ".", "--array", "denton-3222", "--out", "x.out"});
  EXPECT_EQ(several.exit_code, 1);
  ExpectOneSentenceError(several, {"'.' holds 4 tests; a transform reads one"});
}

// An ISO-MME test of head CG accelerometers and angular-rate sensors (codes 11HEAD0000..AC/AV..)
// defines its array: 6aw-cg without --array, on import and transform (docs/formats.md "Arrays from
// channel codes").
TEST(TransformEveryFormat, IsoMmeCodesAtTheCgDefineTheArray) {
  napkin::test_support::TempDir dir;
  synth::RandomMotionOptions motion;
  motion.seed = 4302;
  motion.duration_s = 0.02;
  const synth::SyntheticTest synth = synth::SynthRandomMotion(formats::LoadArray("6aw-cg"), motion);
  formats::WriteIsoMme(synth.signals, synth.array, formats::LoadChannelMap("default"), dir / "cg", "CG1");
  const RunResult from_codes = RunNapkin(dir.path(), {"transform", "cg", "--out", "codes.out"});
  ASSERT_EQ(from_codes.exit_code, 0) << from_codes.err;
  const RunResult given =
      RunNapkin(dir.path(), {"transform", "cg", "--array", "6aw-cg", "--out", "given.out"});
  ASSERT_EQ(given.exit_code, 0) << given.err;
  EXPECT_EQ(ReadText(dir / "codes.out"), ReadText(dir / "given.out"));
  ASSERT_EQ(RunNapkin(dir.path(), {"init"}).exit_code, 0);
  const RunResult imported = RunNapkin(dir.path(), {"import", "cg"});
  ASSERT_EQ(imported.exit_code, 0) << imported.err;
  const nlohmann::json tests =
      nlohmann::json::parse(RunNapkin(dir.path(), {"query", "tests", "--format", "json"}).out);
  ASSERT_EQ(tests.size(), 1u);
  EXPECT_EQ(tests[0].at("test_id"), "cg");
  EXPECT_EQ(tests[0].at("array"), "6aw-cg");
}

}  // namespace
}  // namespace napkin::cli
