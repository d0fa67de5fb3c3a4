// UDS-1992 FCUT end to end (docs/formats.md "UDS-1992 input" and "UDS-1992
// export"): FCUT is the cut-off in Hz of the last filter applied (NHTSA-Tools
// doc/UDS_Vars.txt). Imported channels marked with their J211 class's
// cut-off are not filtered again, and `export --format uds` writes the
// cut-off of the class the exported channels are filtered at — read back by
// napkin's reader and by NHTSA's own Perl reader (../shared/reference/
// nhtsa-uds-perl beside the checkout, read in place; the check is skipped
// with a message where perl or that folder is absent).
#include <gtest/gtest.h>

#include <cstdlib>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/cfc_filter.h"
#include "engine/units.h"
#include "formats/csv.h"
#include "formats/uds1992.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"

#ifndef NAPKIN_NHTSA_UDS_PERL_DIR
#error \
    "NAPKIN_NHTSA_UDS_PERL_DIR (<source>/../shared/reference/nhtsa-uds-perl) is defined by tests/CMakeLists.txt"
#endif

namespace napkin::cli {
namespace {

using namespace napkin::test_support;

// NHTSA's reader: $NAPKIN_NHTSA_UDS_PERL_DIR when set (a worktree whose parent
// has no shared/ folder), else beside the checkout.
fs::path PerlReaderDir() {
  const char* override_dir = std::getenv("NAPKIN_NHTSA_UDS_PERL_DIR");
  return override_dir != nullptr && *override_dir != '\0' ? fs::path(override_dir)
                                                          : fs::path(NAPKIN_NHTSA_UDS_PERL_DIR);
}
const char* const kPerl = "/usr/bin/perl";

// FCUT of each file as NHTSA's uds_read.pl reads it; empty when the reader cannot run.
std::map<std::string, double> PerlFcut(const std::vector<fs::path>& files) {
  const fs::path script = PerlReaderDir() / "uds_read.pl";
  if (!fs::exists(kPerl) || !fs::exists(script)) return {};
  std::vector<std::string> args = {script.string()};
  for (const fs::path& file : files) args.push_back(file.string());
  const CommandResult read = RunProgram(kPerl, args);
  EXPECT_EQ(read.exit_code, 0) << read.err;
  std::map<std::string, double> fcut;
  for (const nlohmann::json& object : nlohmann::json::parse(read.out))
    fcut[fs::path(object.at("file").get<std::string>()).filename().string()] =
        object.at("fcut").get<double>();
  return fcut;
}

bool PerlReaderPresent() {
  if (fs::exists(kPerl) && fs::exists(PerlReaderDir() / "uds_read.pl")) return true;
  std::cout << "[  SKIPPED ] NHTSA's Perl reader not run: " << kPerl << " or "
            << (PerlReaderDir() / "uds_read.pl").string()
            << " is absent (set NAPKIN_NHTSA_UDS_PERL_DIR to the nhtsa-uds-perl folder).\n";
  return false;
}

// Expects FCUT `linear_hz` on the acceleration and velocity files and
// `angular_hz` on the angular ones of an export in `folder`, by napkin's and
// NHTSA's readers.
void ExpectExportedFcut(const fs::path& folder, const std::string& test, double linear_hz,
                        double angular_hz) {
  const std::map<std::string, double> expected = {
      {"F" + test + "AM00.00X", linear_hz},  {"F" + test + "VM00.00Z", linear_hz},
      {"B" + test + "ROTV.00Y", angular_hz}, {"F" + test + "ROTA.00X", angular_hz},
      {"F" + test + "DCOS.033", angular_hz}, {"F" + test + "ROTD.00Z", angular_hz},
      {"F" + test + "ROTV.00X", angular_hz}};
  std::vector<fs::path> files;
  for (const auto& [name, fcut] : expected) {
    files.push_back(folder / name);
    EXPECT_EQ(formats::ReadUds1992(folder / name).filter_cutoff_hz, fcut) << name;
  }
  if (!PerlReaderPresent()) return;
  const std::map<std::string, double> perl = PerlFcut(files);
  ASSERT_EQ(perl.size(), expected.size());
  for (const auto& [name, fcut] : expected) EXPECT_EQ(perl.at(name), fcut) << name << " (NHTSA's reader)";
}

TEST(CliUdsFcut, ExportWritesTheCutoffOfTheClassApplied) {
  TempDir dir;
  synth::RandomMotionOptions options;
  options.seed = 93;
  options.duration_s = 0.05;
  const synth::SyntheticTest synth = synth::SynthRandomMotion(formats::LoadArray("6aw-cg"), options);
  formats::WriteSignalsCsv(synth.signals, dir / "t93.csv");
  ASSERT_EQ(RunNapkin(dir.path(), {"init"}).exit_code, 0);
  const RunResult import = RunNapkin(dir.path(), {"import", "--array", "6aw-cg", "t93.csv"});
  ASSERT_EQ(import.exit_code, 0) << import.err;
  WriteText(dir / "c600.json", R"({"name": "c600", "filter": {"linear_cfc": 600, "angular_rate_cfc": 180}})");
  WriteText(dir / "raw.json",
            R"({"name": "raw", "filter": {"linear_cfc": "none", "angular_rate_cfc": "none"}})");
  struct Case {
    const char* config;
    double linear_hz, angular_hz;
  };
  for (const Case& c :
       {Case{"default", 1650.0, 100.0}, Case{"c600.json", 1000.0, 300.0}, Case{"raw.json", 0, 0}}) {
    SCOPED_TRACE(c.config);
    const RunResult run = RunNapkin(dir.path(), {"run", "--config", c.config});
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const std::string out = std::string("uds-") + c.config;
    const RunResult exported = RunNapkin(
        dir.path(), {"export", "--test", "t93", "--config", c.config, "--format", "uds", "--out", out});
    ASSERT_EQ(exported.exit_code, 0) << exported.err;
    ExpectExportedFcut(dir / out, "t93", c.linear_hz, c.angular_hz);
  }
}

// A 6aw-cg head as UDS-1992 files: CG accelerations filtered at CFC 600 (FCUT
// 1000 Hz) and angular rates at CFC 180 (FCUT 300 Hz).
void WritePrefilteredUds(const synth::SyntheticTest& synth, const fs::path& folder) {
  fs::create_directories(folder);
  const char* axes[3] = {"XL", "YL", "ZL"};
  for (Eigen::Index c = 0; c < 6; ++c) {
    const bool rate = c >= 3;
    Eigen::VectorXd column = synth.signals.samples.col(c);
    engine::CfcFilterInPlace(column, synth.signals.dt_s, rate ? engine::kCfc180 : engine::kCfc600);
    formats::UdsChannel channel;
    channel.test_number = 94;
    channel.senatt = "HEAD CG";
    channel.axis = axes[c % 3];
    channel.ytyp = rate ? "ANGULAR VELOCITY" : "ACCELERATION";
    channel.yunits = rate ? "DEG/SEC" : "G'S";
    channel.nfp = static_cast<int>(std::lround(synth.signals.t0_s / synth.signals.dt_s));
    channel.del_s = synth.signals.dt_s;
    channel.filter_cutoff_hz = rate ? 300.0 : 1000.0;
    for (Eigen::Index k = 0; k < column.size(); ++k)
      channel.values.push_back(rate ? column[k] * engine::kDegPerRad : column[k]);
    formats::WriteUds1992(channel, folder / ("v0094.00" + std::to_string(c + 1)));
  }
}

TEST(CliUdsFcut, PrefilteredChannelsAreNotFilteredAgainAndExportSaysTheirClass) {
  TempDir dir;
  synth::RandomMotionOptions options;
  options.seed = 94;
  options.duration_s = 0.05;
  const synth::SyntheticTest synth = synth::SynthRandomMotion(formats::LoadArray("6aw-cg"), options);
  WritePrefilteredUds(synth, dir / "uds");
  ASSERT_EQ(RunNapkin(dir.path(), {"init"}).exit_code, 0);
  const RunResult import = RunNapkin(dir.path(), {"import", "--array", "6aw-cg", "uds"});
  ASSERT_EQ(import.exit_code, 0) << import.err;
  // Default config: CFC 1000 on the accelerometers (covered by their CFC 600), CFC 60 on the
  // rate sensors (narrower than their CFC 180: applied).
  const RunResult run = RunNapkin(dir.path(), {"run"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const RunResult query =
      RunNapkin(dir.path(), {"query", "conditioning", "--where", "test_id=v0094", "--format", "json"});
  ASSERT_EQ(query.exit_code, 0) << query.err;
  std::map<std::string, std::string> filter;
  for (const nlohmann::json& row : nlohmann::json::parse(query.out))
    filter[row.at("channel").get<std::string>()] = row.at("filter").get<std::string>();
  for (const char* slot : {"cg_x", "cg_y", "cg_z"})
    EXPECT_EQ(filter[slot], "none, prefiltered at CFC 600") << slot;
  for (const char* slot : {"ars_x", "ars_y", "ars_z"}) EXPECT_EQ(filter[slot], "CFC 60") << slot;

  const RunResult exported =
      RunNapkin(dir.path(), {"export", "--test", "v0094", "--format", "uds", "--out", "out"});
  ASSERT_EQ(exported.exit_code, 0) << exported.err;
  ExpectExportedFcut(dir / "out", "v0094", 1000.0, 100.0);
}

}  // namespace
}  // namespace napkin::cli
