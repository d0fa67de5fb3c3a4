// Ingest of real lab data as it comes (issue 10 items 2, 3, 5): several
// dummies in one test become one catalogue test each, UDS-1992 groups find
// their channels through the default map, INIVEL becomes the initial
// velocity, the files' test information is stored, CSV columns are mapped,
// and channels of different spans are cropped with a note.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "db/catalogue.h"
#include "engine/units.h"
#include "formats/uds1992.h"
#include "ingest/import.h"
#include "tests/support/db/catalogue_inspector.h"
#include "tests/support/isomme_generator.h"
#include "tests/support/test_support.h"
#include "tests/support/zip_writer.h"

namespace napkin::ingest {
namespace {

namespace fs = std::filesystem;
using test_support::TempDir;

db::TestRow ReadByExternalId(db::Catalogue& catalogue, const std::string& id) {
  const std::optional<db::TestId> test = catalogue.FindTestByExternalId(id);
  if (!test) throw std::runtime_error("no test " + id);
  return catalogue.ReadTest(*test);
}

std::vector<std::string> ResultIds(const ImportReport& report) {
  std::vector<std::string> ids;
  for (const ImportResult& result : report.results) ids.push_back(result.test_id);
  return ids;
}

double DegToRad() { return engine::SignalUnitToSi("deg/s")->si_per_unit; }

// The catalogue holds exactly the generated test's two heads, each sample
// as written (g into g; deg/s into rad/s), with its test information.
void ExpectTheTwoGeneratedHeads(db::Catalogue& catalogue, const ImportReport& report,
                                const test_support::GeneratedIsoMme& generated, const std::string& id) {
  ASSERT_EQ(report.imported, 2) << report.results.front().message;
  EXPECT_EQ(report.failed, 0);
  EXPECT_EQ(ResultIds(report), (std::vector<std::string>{id + "/11", id + "/13"}));
  EXPECT_EQ(catalogue.ReadAllTests().size(), 2U);
  for (const test_support::GeneratedHead& head : generated.heads) {
    const db::TestRow record = ReadByExternalId(catalogue, id + "/" + head.position);
    const engine::TestSignals signals = catalogue.ReadTestSignals(record.id);
    ASSERT_EQ(signals.slots, (std::vector<std::string>{"cg_x", "cg_y", "cg_z", "ars_x", "ars_y", "ars_z"}));
    ASSERT_EQ(signals.size(), head.acc_g.rows());
    EXPECT_DOUBLE_EQ(signals.t0_s, -0.01);
    for (Eigen::Index k = 0; k < signals.size(); ++k)
      for (int a = 0; a < 3; ++a) {
        ASSERT_EQ(signals.samples(k, a), head.acc_g(k, a));  // g into g: the value as written
        ASSERT_EQ(signals.samples(k, 3 + a), head.omega_degps(k, a) * DegToRad());
      }
    const nlohmann::json metadata = nlohmann::json::parse(record.metadata_json);
    EXPECT_EQ(metadata["channel_map"], "default");
    EXPECT_EQ(metadata["test"]["position"], head.position);
    EXPECT_EQ(metadata["test"]["dummy"], head.dummy_code);
    EXPECT_EQ(metadata["test"]["test_number"], "MD0001");
    EXPECT_EQ(metadata["test"]["title"], generated.title);
    EXPECT_EQ(metadata["test"]["vehicle"], generated.vehicle);  // ISO-8859-1 in the file, UTF-8 here
    EXPECT_EQ(metadata["test"]["laboratory"], generated.laboratory);
    EXPECT_EQ(metadata["test"]["date"], generated.date);
  }
}

// Import time is measured in bench/bench_import.cpp (BM_ImportTwoDummyIsoMme).
TEST(MultiDummyImportTest, TwoDummyIsoMmeTestImportsExactlyItsTwoHeads) {
  TempDir dir;
  const test_support::GeneratedIsoMme generated = test_support::WriteMultiDummyIsoMme(dir / "MD0001");
  ASSERT_EQ(generated.codes.size(), 120U);
  db::Catalogue catalogue = db::Catalogue::Open((dir / "c.db").string());
  ImportOptions options;
  options.array = "6aw-cg";

  const ImportReport report = ImportTests(catalogue, {(dir / "MD0001").string()}, options);
  ExpectTheTwoGeneratedHeads(catalogue, report, generated, "MD0001");

  // The two heads are distinct content: importing again skips both.
  const ImportReport again = ImportTests(catalogue, {(dir / "MD0001").string()}, options);
  EXPECT_EQ(again.skipped, 2);
  EXPECT_EQ(again.imported, 0);

  db::QueryRequest request;
  request.where.push_back(db::WhereExpression{
      db::WhereComparison{"position", db::ComparisonOperator::kEqual, std::string("13")}});
  const db::Table table = catalogue.Query(db::QueryKind::kTests, request);
  ASSERT_EQ(table.rows.size(), 1U);
  EXPECT_EQ(std::get<std::string>(table.rows[0][0]), "MD0001/13");
}

TEST(MultiDummyImportTest, ZippedTwoDummyIsoMmeTestImportsTheSameTwoHeads) {
  TempDir dir;
  const test_support::GeneratedIsoMme generated = test_support::WriteMultiDummyIsoMme(dir / "MD0001");
  // As NHTSA publishes a test: one archive, the test folder at its top.
  test_support::WriteZip(dir / "MD0001.zip", test_support::FolderEntries(dir / "MD0001", "MD0001/"));
  fs::remove_all(dir / "MD0001");
  db::Catalogue catalogue = db::Catalogue::Open((dir / "c.db").string());
  ImportOptions options;
  options.array = "6aw-cg";

  const ImportReport report = ImportTests(catalogue, {(dir / "MD0001.zip").string()}, options);
  ExpectTheTwoGeneratedHeads(catalogue, report, generated, "MD0001");
  for (const test_support::GeneratedHead& head : generated.heads) {
    const nlohmann::json metadata =
        nlohmann::json::parse(ReadByExternalId(catalogue, "MD0001/" + head.position).metadata_json);
    EXPECT_EQ(metadata["format"], "iso-mme");
    EXPECT_EQ(metadata["archive"], "zip");
  }
  EXPECT_EQ(ImportTests(catalogue, {(dir / "MD0001.zip").string()}, options).skipped, 2);
}

TEST(MultiDummyImportTest, PositionTakesOneHeadUnderTheIdAndHashOfTheFullImport) {
  TempDir dir;
  test_support::WriteMultiDummyIsoMme(dir / "MD0001", {.channel_count = 40, .samples = 50});
  db::Catalogue catalogue = db::Catalogue::Open((dir / "c.db").string());
  ImportOptions options;
  options.array = "6aw-cg";
  options.position = "13";
  const ImportReport one = ImportTests(catalogue, {(dir / "MD0001").string()}, options);
  ASSERT_EQ(one.imported, 1) << one.results.front().message;
  EXPECT_EQ(ResultIds(one), std::vector<std::string>{"MD0001/13"});

  options.position.reset();
  const ImportReport all = ImportTests(catalogue, {(dir / "MD0001").string()}, options);
  EXPECT_EQ(all.imported, 1);
  EXPECT_EQ(all.skipped, 1);
  EXPECT_EQ(ResultIds(all), (std::vector<std::string>{"MD0001/11", "MD0001/13"}));
}

TEST(MultiDummyImportTest, AmbiguousOrMissingPositionIsOneSentenceAndLeavesTheCatalogueIdentical) {
  TempDir dir;
  test_support::WriteMultiDummyIsoMme(dir / "MD0001", {.channel_count = 40, .samples = 50});
  db::Catalogue catalogue = db::Catalogue::Open((dir / "c.db").string());
  ImportOptions options;
  options.array = "6aw-cg";
  options.test_id = "driver";  // one test expected, two heads found
  const std::string before = db::CatalogueInspector(catalogue).Dump();

  const ImportReport ambiguous = ImportTests(catalogue, {(dir / "MD0001").string()}, options);
  ASSERT_EQ(ambiguous.failed, 1);
  EXPECT_EQ(ambiguous.imported, 0);
  const std::string& message = ambiguous.results.front().message;
  EXPECT_NE(message.find("positions 11 and 13"), std::string::npos) << message;
  EXPECT_NE(message.find("--position"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos);
  EXPECT_EQ(message.back(), '.');
  EXPECT_EQ(message.find(". "), std::string::npos) << message;  // one sentence
  EXPECT_EQ(db::CatalogueInspector(catalogue).Dump(), before);

  options.test_id.reset();
  options.position = "12";
  const ImportReport missing = ImportTests(catalogue, {(dir / "MD0001").string()}, options);
  ASSERT_EQ(missing.failed, 1);
  EXPECT_NE(
      missing.results.front().message.find("no dummy head at position 12 (it holds position 11 and 13)"),
      std::string::npos)
      << missing.results.front().message;
  EXPECT_EQ(db::CatalogueInspector(catalogue).Dump(), before);

  // --test-id with --position is not ambiguous: that head under that id.
  options.test_id = "driver";
  options.position = "11";
  const ImportReport driver = ImportTests(catalogue, {(dir / "MD0001").string()}, options);
  ASSERT_EQ(driver.imported, 1) << driver.results.front().message;
  EXPECT_EQ(ResultIds(driver), std::vector<std::string>{"driver"});
}

// A UDS-1992 channel of a generated test: a half-sine pulse, INIVEL in km/h (DIMSYS MET).
formats::UdsChannel UdsHeadChannel(const std::string& senloc, const std::string& axis, bool rate,
                                   double amplitude, double inivel_kmh) {
  formats::UdsChannel channel;
  channel.test_number = 4321;
  channel.title = "FRONTAL BARRIER 56 KMH";
  channel.test_source = "TRC OHIO";
  channel.make = "DODGE";
  channel.model = "NEON";
  channel.occupant_type = "H3";
  channel.dummy_size = "50";
  channel.senatt = "HEAD CG";
  channel.senloc = senloc;
  channel.axis = axis;
  channel.ytyp = rate ? "ANGULAR VELOCITY" : "ACCELERATION";
  channel.yunits = rate ? "DEG/SEC" : "G'S";
  channel.initial_velocity = inivel_kmh;
  channel.nfp = -100;
  for (int k = 0; k < 600; ++k) channel.values.push_back(amplitude * std::sin(0.01 * k));
  return channel;
}

// Writes a two-dummy UDS-1992 group (SENLOC 01 driver, 03 passenger): 12 head channels plus two
// vehicle channels, INIVEL along X of 56 km/h on every head accelerometer.
void WriteTwoDummyUds(const fs::path& folder) {
  fs::create_directories(folder);
  int file = 0;
  auto write = [&](const formats::UdsChannel& channel) {
    char name[32];
    std::snprintf(name, sizeof(name), "v4321.%03d", ++file);
    formats::WriteUds1992(channel, folder / name);
  };
  for (const std::string senloc : {"01", "03"}) {
    const double scale = senloc == "01" ? 1.0 : 2.0;
    write(UdsHeadChannel(senloc, "XL", false, -30 * scale, 56.0));
    write(UdsHeadChannel(senloc, "YL", false, 5 * scale, 0.0));
    write(UdsHeadChannel(senloc, "ZL", false, 10 * scale, 0.0));
    write(UdsHeadChannel(senloc, "XL", true, 100 * scale, 0.0));
    write(UdsHeadChannel(senloc, "YL", true, 200 * scale, 0.0));
    write(UdsHeadChannel(senloc, "ZL", true, 300 * scale, 0.0));
  }
  formats::UdsChannel vehicle = UdsHeadChannel("", "XG", false, 20, 56.0);
  vehicle.senatt = "VEHICLE CG";
  write(vehicle);
  vehicle.senatt = "LEFT REAR SEAT";
  write(vehicle);
}

TEST(UdsImportTest, WithoutAMapTheDefaultMapFindsEachDummyAndInivelIsTheInitialVelocity) {
  TempDir dir;
  WriteTwoDummyUds(dir / "uds");
  db::Catalogue catalogue = db::Catalogue::Open((dir / "c.db").string());
  ImportOptions options;
  options.array = "6aw-cg";
  const double theta = 0.3;
  options.orientation_rad = {0.0, theta, 0.0};
  const ImportReport report = ImportTests(catalogue, {(dir / "uds").string()}, options);
  ASSERT_EQ(report.imported, 2) << report.results.front().message;
  EXPECT_EQ(ResultIds(report), (std::vector<std::string>{"v4321/01", "v4321/03"}));

  const db::TestRow passenger = ReadByExternalId(catalogue, "v4321/03");
  const engine::TestSignals signals = catalogue.ReadTestSignals(passenger.id);
  EXPECT_EQ(signals.t0_s, -100 * 1e-4);
  EXPECT_FLOAT_EQ(signals.samples(50, 0), static_cast<float>(-60 * std::sin(0.5)));
  EXPECT_FLOAT_EQ(signals.samples(50, 5), static_cast<float>(600 * std::sin(0.5)) * DegToRad());
  // 56 km/h along the head's x, rotated by R0 = Ry(theta): (v cos theta, 0, -v sin theta).
  const double v = 56.0 / 3.6;
  EXPECT_NEAR(passenger.initial_state.velocity_fixed_mps.x(), v * std::cos(theta), 1e-5);
  EXPECT_NEAR(passenger.initial_state.velocity_fixed_mps.y(), 0.0, 1e-12);
  EXPECT_NEAR(passenger.initial_state.velocity_fixed_mps.z(), -v * std::sin(theta), 1e-5);
  const nlohmann::json metadata = nlohmann::json::parse(passenger.metadata_json);
  EXPECT_EQ(metadata["initial_velocity"], "inivel");
  EXPECT_EQ(metadata["channel_map"], "default");
  EXPECT_EQ(metadata["test"], (nlohmann::json{{"test_number", "4321"},
                                              {"title", "FRONTAL BARRIER 56 KMH"},
                                              {"vehicle", "DODGE NEON"},
                                              {"dummy", "H3 50"},
                                              {"position", "03"},
                                              {"laboratory", "TRC OHIO"}}));

  // --initial-velocity wins over INIVEL.
  db::Catalogue other = db::Catalogue::Open((dir / "d.db").string());
  options.initial_velocity_mps = {1.0, 2.0, 3.0};
  options.position = "01";
  ASSERT_EQ(ImportTests(other, {(dir / "uds").string()}, options).imported, 1);
  const db::TestRow driver = ReadByExternalId(other, "v4321/01");
  EXPECT_EQ(driver.initial_state.velocity_fixed_mps, Eigen::Vector3d(1.0, 2.0, 3.0));
  EXPECT_EQ(nlohmann::json::parse(driver.metadata_json).count("initial_velocity"), 0U);
}

TEST(IsoMmeImportTest, ChannelsOfDifferentSpansAreCroppedWithANoteRecordedWithTheTest) {
  TempDir dir;
  test_support::WriteMultiDummyIsoMme(
      dir / "T1", {.test_number = "T1", .head_positions = {"11"}, .channel_count = 12, .samples = 40});
  // Drop the last five samples of the head's y accelerometer (channel 3: acc x, rate x, acc y ...).
  const fs::path file = dir / "T1" / "Channel" / "T1.003";
  std::ifstream in(file, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  const std::string declared = "Number of samples           :40";
  ASSERT_NE(text.find(declared), std::string::npos);
  text.replace(text.find(declared), declared.size(), "Number of samples           :35");
  for (int i = 0; i < 5; ++i) text.erase(text.rfind("\r\n", text.size() - 3) + 2);
  std::ofstream(file, std::ios::binary) << text;

  db::Catalogue catalogue = db::Catalogue::Open((dir / "c.db").string());
  ImportOptions options;
  options.array = "6aw-cg";
  const ImportReport report = ImportTests(catalogue, {(dir / "T1").string()}, options);
  ASSERT_EQ(report.imported, 1) << report.results.front().message;
  EXPECT_EQ(report.results.front().test_id, "T1");  // one dummy: the id is the folder's
  ASSERT_EQ(report.results.front().warnings.size(), 1U);
  const std::string& note = report.results.front().warnings.front();
  EXPECT_NE(note.find("cropped to the common span -0.01 s to -0.0066 s"), std::string::npos) << note;
  EXPECT_NE(note.find("11HEAD0000H3ACXA (5 samples)"), std::string::npos) << note;
  EXPECT_EQ(note.find("11HEAD0000H3ACYA"), std::string::npos) << note;  // the short one lost nothing
  const db::TestRow record = ReadByExternalId(catalogue, "T1");
  EXPECT_EQ(catalogue.ReadTestSignals(record.id).size(), 35);
  const nlohmann::json metadata = nlohmann::json::parse(record.metadata_json);
  ASSERT_EQ(metadata["notes"].size(), 1U);
  EXPECT_NE(note.find(metadata["notes"][0].get<std::string>()),
            std::string::npos);  // the warning names the folder
  EXPECT_EQ(metadata["test"]["position"], "11");
}

TEST(CsvImportTest, ColumnOptionsAndTheMapsColumnEntriesNameTheColumns) {
  TempDir dir;
  std::ofstream(dir / "lab.csv")
      << "Time,AX,AY,AZ,RX,RY,RZ,extra\n0,1,2,3,4,5,6,7\n0.001,1.5,2.5,3.5,4.5,5.5,6.5,7.5\n";
  std::ofstream(dir / "map.json")
      << R"({"name": "lab", "slots": {"cg_x": {"column": "AX"}, "cg_y": {"column": "AY"}, "cg_z": {"column": "AZ"},
            "ars_x": {"column": "RX"}, "ars_y": {"column": "RY"}, "ars_z": {"column": "nope"}}})";
  db::Catalogue catalogue = db::Catalogue::Open((dir / "c.db").string());
  ImportOptions options;
  options.array = "6aw-cg";
  options.channel_map = (dir / "map.json").string();
  options.csv_columns = {"time_s=Time", "ars_z=RZ"};  // --column wins over the map's entry
  const ImportReport report = ImportTests(catalogue, {(dir / "lab.csv").string()}, options);
  ASSERT_EQ(report.imported, 1) << report.results.front().message;
  ASSERT_EQ(report.results.front().warnings.size(), 1U);
  EXPECT_NE(report.results.front().warnings[0].find("column \"extra\""), std::string::npos);
  const engine::TestSignals signals = catalogue.ReadTestSignals(ReadByExternalId(catalogue, "lab").id);
  EXPECT_EQ(signals.dt_s, 0.001);
  Eigen::MatrixXd expected(2, 6);
  expected << 1, 2, 3, 4, 5, 6, 1.5, 2.5, 3.5, 4.5, 5.5, 6.5;
  EXPECT_EQ(signals.samples, expected);

  options.csv_columns = {"ars_q=RZ"};
  EXPECT_THROW(ImportTests(catalogue, {(dir / "lab.csv").string()}, options), UsageError);
  options.csv_columns = {"ars_z"};
  EXPECT_THROW(ImportTests(catalogue, {(dir / "lab.csv").string()}, options), UsageError);
}

}  // namespace
}  // namespace napkin::ingest
