// UDS-1992 INIVEL off the array origin (docs/formats.md "UDS-1992 input"):
// the Denton NAP's CG triad sits 0.203 in from the origin, as real arrays
// do; its channels' INIVEL is the initial velocity all the same (a rigid
// body without initial rotation moves at one velocity everywhere; with an
// initial angular velocity omega the sensor at r moves at v + omega x r).
// INIVEL that napkin does not use is reported naming the channel and why.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "db/catalogue.h"
#include "formats/array_json.h"
#include "formats/uds1992.h"
#include "ingest/dummy_heads.h"
#include "ingest/import.h"
#include "tests/support/test_support.h"

namespace napkin::ingest {
namespace {

namespace fs = std::filesystem;
using test_support::TempDir;

// Nine files in the report's Table 2-1 order (cg_x, cg_y, cg_z, yarm_z,
// yarm_x, xarm_z, xarm_y, zarm_x, zarm_y), INIVEL in km/h (DIMSYS MET) per file.
std::vector<fs::path> WriteNapUds(const fs::path& folder, const std::vector<double>& inivel_kmh) {
  fs::create_directories(folder);
  const char* axes[9] = {"XL", "YL", "ZL", "ZL", "XL", "ZL", "YL", "XL", "YL"};
  std::vector<fs::path> files;
  for (int f = 0; f < 9; ++f) {
    formats::UdsChannel channel;
    channel.test_number = 77;
    channel.senatt = "HEAD";
    channel.axis = axes[f];
    channel.initial_velocity = inivel_kmh.at(static_cast<std::size_t>(f));
    channel.nfp = -50;
    for (int k = 0; k < 400; ++k) channel.values.push_back((f + 1) * std::sin(0.01 * k));
    char name[32];
    std::snprintf(name, sizeof(name), "n0077.%03d", f + 1);
    files.push_back(folder / name);
    formats::WriteUds1992(channel, files.back());
  }
  return files;
}

// The INIVEL warnings of an import, in order.
std::vector<std::string> InivelWarnings(const ImportReport& report) {
  std::vector<std::string> found;
  for (const ImportResult& result : report.results)
    for (const std::string& warning : result.warnings)
      if (warning.find("INIVEL") != std::string::npos) found.push_back(warning);
  return found;
}

TEST(UdsInivel, CgTriadOffTheOriginGivesTheInitialVelocity) {
  TempDir dir;
  // 56 km/h along x on every x channel (cg_x, yarm_x, zarm_x), as NHTSA's files carry it.
  WriteNapUds(dir / "nap", {56, 0, 0, 0, 56, 0, 0, 56, 0});
  db::Catalogue catalogue = db::Catalogue::Open((dir / "c.db").string());
  ImportOptions options;
  options.array = "denton-3222";
  const ImportReport report = ImportTests(catalogue, {(dir / "nap").string()}, options);
  ASSERT_EQ(report.imported, 1) << report.results.front().message;
  const db::TestRow record = catalogue.ReadTest(*catalogue.FindTestByExternalId("n0077"));
  EXPECT_NEAR(record.initial_state.velocity_fixed_mps.x(), 56.0 / 3.6, 1e-5);
  EXPECT_EQ(record.initial_state.velocity_fixed_mps.y(), 0.0);
  EXPECT_EQ(record.initial_state.velocity_fixed_mps.z(), 0.0);
  EXPECT_EQ(nlohmann::json::parse(record.metadata_json)["initial_velocity"], "inivel");
  EXPECT_TRUE(InivelWarnings(report).empty()) << InivelWarnings(report).front();
}

TEST(UdsInivel, InivelNotUsedIsReportedNamingTheChannelAndWhy) {
  TempDir dir;
  // zarm_x (file 8) says 50 km/h where cg_x, nearer the CG, says 56.
  const std::vector<fs::path> files = WriteNapUds(dir / "nap", {56, 0, 0, 0, 56, 0, 0, 50, 0});
  db::Catalogue catalogue = db::Catalogue::Open((dir / "c.db").string());
  ImportOptions options;
  options.array = "denton-3222";
  const ImportReport report = ImportTests(catalogue, {(dir / "nap").string()}, options);
  ASSERT_EQ(report.imported, 1) << report.results.front().message;
  const db::TestRow record = catalogue.ReadTest(*catalogue.FindTestByExternalId("n0077"));
  EXPECT_NEAR(record.initial_state.velocity_fixed_mps.x(), 56.0 / 3.6, 1e-5);
  std::vector<std::string> warnings = InivelWarnings(report);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].rfind(files[7].string() + " (slot zarm_x, INIVEL 13.888", 0), 0u) << warnings[0];
  EXPECT_NE(warnings[0].find("INIVEL is not used, as it differs from the x velocity taken from " +
                             files[0].string() + " (slot cg_x), the sensor nearest the CG."),
            std::string::npos)
      << warnings[0];

  // --initial-velocity gives the velocity: the files' INIVEL is not used, and the import says so.
  db::Catalogue other = db::Catalogue::Open((dir / "d.db").string());
  options.initial_velocity_mps = {1.0, 2.0, 3.0};
  const ImportReport given = ImportTests(other, {(dir / "nap").string()}, options);
  ASSERT_EQ(given.imported, 1) << given.results.front().message;
  warnings = InivelWarnings(given);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_EQ(warnings[1],
            "n0077: the INIVEL its files record is not used, as --initial-velocity gives the "
            "initial velocity.");
}

// A linear sensor at r with INIVEL = axis . (v + omega x r) gives v; an
// angular-rate channel and a skewed sensor are reported.
TEST(UdsInivel, InitialRotationIsTakenOffAndOtherChannelsAreReported) {
  engine::ArrayGeometry array = formats::LoadArray("denton-3222");
  const Eigen::Vector3d v(15.0, -2.0, 0.5);
  const Eigen::Vector3d omega(3.0, -5.0, 7.0);
  std::vector<formats::RawChannel> channels(array.sensors.size());
  std::vector<std::size_t> channel_of_sensor;
  for (std::size_t s = 0; s < array.sensors.size(); ++s) {
    const engine::Sensor& sensor = array.sensors[s];
    channels[s].source = "file" + std::to_string(s);
    channels[s].initial_velocity_mps = sensor.axis_body.dot(v + omega.cross(sensor.position_body_m));
    channel_of_sensor.push_back(s);
  }
  FileInitialVelocity found = InitialVelocityBody(channels, channel_of_sensor, array, omega);
  ASSERT_TRUE(found.velocity_body_mps.has_value());
  EXPECT_NEAR((*found.velocity_body_mps - v).norm(), 0.0, 1e-12);
  EXPECT_TRUE(found.unused.empty()) << found.unused.front();
  // Without the rotation the arms' INIVEL (omega x r differs along them) disagrees with the CG triad's.
  found = InitialVelocityBody(channels, channel_of_sensor, array);
  EXPECT_EQ(found.unused.size(), 6u);

  array.sensors[0].kind = engine::SensorKind::kAngularRate;
  array.sensors[1].axis_body = Eigen::Vector3d(0.6, 0.8, 0.0);
  found = InitialVelocityBody(channels, channel_of_sensor, array, omega);
  ASSERT_GE(found.unused.size(), 2u);
  EXPECT_EQ(found.unused[0].rfind("file0 (slot cg_x, INIVEL ", 0), 0u) << found.unused[0];
  EXPECT_NE(found.unused[0].find("the channel feeds an angular-rate sensor."), std::string::npos);
  EXPECT_EQ(found.unused[1].rfind("file1 (slot cg_y, INIVEL ", 0), 0u) << found.unused[1];
  EXPECT_NE(found.unused[1].find("the sensor senses along no body axis."), std::string::npos);
}

}  // namespace
}  // namespace napkin::ingest
