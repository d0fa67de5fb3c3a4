// Issue 10 acceptance: real head-CG accelerations of three NHTSA frontal crash
// tests (../shared/data/nhtsa-frontal beside the checkout; never copied into
// the repository) imported through the acceleration-only array 3a-cg as CSV,
// as an ISO-MME folder and as UDS-1992 files (both written here from the data
// with napkin's own writers), run with the default config and queried: HIC15,
// HIC36 and unlimited HIC with their windows, peak resultant and a3ms equal
// NHTSA's own programs (the folder README's reference table).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "formats/channel_map.h"
#include "formats/isomme.h"
#include "formats/uds1992.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"

#ifndef NAPKIN_NHTSA_FRONTAL_DIR
#error "NAPKIN_NHTSA_FRONTAL_DIR (<source>/../shared/data/nhtsa-frontal) is defined by tests/CMakeLists.txt"
#endif

namespace napkin::cli {
namespace {

using namespace napkin::test_support;

// The README's table: NHTSA-Tools (RmBias over all t < 0, BWFilt at the SAE
// J211 CFC 1000 design frequency, resultant, HIC), windows in ms.
struct NhtsaReference {
  const char* test;
  double hic15, hic15_t1_ms, hic15_t2_ms;
  double hic36, hic36_t1_ms, hic36_t2_ms;
  double hic, hic_t1_ms, hic_t2_ms;
  double peak_g, a3ms_g;
};

constexpr NhtsaReference kReference[] = {
    {"corolla", 205.727, 74.7, 89.7, 345.510, 67.6, 103.6, 373.413, 51.1, 104.2, 48.4305, 47.1214},
    {"crv", 177.693, 74.5, 89.5, 330.697, 58.7, 94.7, 343.178, 55.8, 98.0, 46.9349, 44.4579},
    {"f150", 189.339, 73.1, 88.1, 317.976, 65.3, 101.3, 321.224, 63.4, 103.1, 47.0667, 45.9870},
};

// Where the recordings are: $NAPKIN_NHTSA_FRONTAL_DIR when set (a worktree
// whose parent has no shared/ folder), else beside the checkout.
fs::path DataDir() {
  const char* override_dir = std::getenv("NAPKIN_NHTSA_FRONTAL_DIR");
  return override_dir != nullptr && *override_dir != '\0' ? fs::path(override_dir)
                                                          : fs::path(NAPKIN_NHTSA_FRONTAL_DIR);
}

// One recording: the text lines of its samples (time_s,ax_g,ay_g,az_g) and the
// same as signals (slots cg_x, cg_y, cg_z).
struct Recording {
  std::vector<std::string> data_lines;
  engine::TestSignals signals;
};

Recording ReadRecording(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(util::Trim(line), "time_s,ax_g,ay_g,az_g") << path;
  Recording recording;
  std::vector<std::array<double, 4>> rows;
  while (std::getline(in, line)) {
    if (util::Trim(line).empty()) continue;
    recording.data_lines.emplace_back(util::Trim(line));
    std::array<double, 4> row{};
    std::stringstream fields(recording.data_lines.back());
    std::string field;
    for (double& value : row) {
      std::getline(fields, field, ',');
      value = std::stod(field);
    }
    rows.push_back(row);
  }
  engine::TestSignals& signals = recording.signals;
  signals.slots = {"cg_x", "cg_y", "cg_z"};
  signals.t0_s = rows.front()[0];
  signals.dt_s = (rows.back()[0] - rows.front()[0]) / static_cast<double>(rows.size() - 1);
  signals.samples.resize(static_cast<Eigen::Index>(rows.size()), 3);
  for (std::size_t k = 0; k < rows.size(); ++k)
    for (int c = 0; c < 3; ++c) signals.samples(static_cast<Eigen::Index>(k), c) = rows[k][c + 1];
  return recording;
}

// The CSV napkin reads: the same numbers, the array's slot names as columns.
void WriteNapkinCsv(const Recording& recording, const fs::path& path) {
  std::ofstream out(path, std::ios::binary);
  out << "time_s,cg_x,cg_y,cg_z\n";
  for (const std::string& line : recording.data_lines) out << line << '\n';
}

// Three UDS-1992 channel files, SENATT "HEAD CG", AXIS XL/YL/ZL, first sample
// at NFP * DEL = t0.
void WriteUdsFiles(const Recording& recording, const fs::path& folder, const std::string& stem) {
  const engine::TestSignals& signals = recording.signals;
  const char* axes[3] = {"XL", "YL", "ZL"};
  for (int c = 0; c < 3; ++c) {
    formats::UdsChannel channel;
    channel.test_name = stem;
    channel.title = "NHTSA frontal test, driver head CG";
    channel.curve_name = std::string("HEAD CG ") + axes[c];
    channel.senatt = "HEAD CG";
    channel.senloc = "DRIVER";
    channel.axis = axes[c];
    channel.del_s = signals.dt_s;
    channel.nfp = static_cast<int>(std::lround(signals.t0_s / signals.dt_s));
    channel.values.assign(signals.samples.col(c).begin(), signals.samples.col(c).end());
    formats::WriteUds1992(channel, folder / (stem + ".00" + std::to_string(c + 1)));
  }
}

void ExpectRelative(double actual, double expected, double tolerance, const std::string& what) {
  EXPECT_LE(std::abs(actual - expected), tolerance * std::abs(expected))
      << what << ": " << actual << " against NHTSA's " << expected;
}

// A window end (s) on the sample the README gives in ms (0.1 ms = one sample).
void ExpectSameSample(double actual_s, double expected_ms, double dt_s, const std::string& what) {
  EXPECT_LE(std::abs(actual_s * 1000.0 - expected_ms), 0.5 * dt_s * 1000.0)
      << what << ": " << actual_s * 1000.0 << " ms against NHTSA's " << expected_ms << " ms";
}

TEST(NhtsaFrontal, AccelerationOnlyImportsInEveryFormatMatchNhtsasPrograms) {
  const fs::path data = DataDir();
  for (const NhtsaReference& reference : kReference)
    if (!fs::exists(data / (std::string(reference.test) + ".csv")))
      GTEST_SKIP() << "the NHTSA frontal recordings are not at " << data.string()
                   << " (they sit beside the checkout in CI, ../shared/data/nhtsa-frontal; set "
                      "NAPKIN_NHTSA_FRONTAL_DIR to their folder to run this test).";

  TempDir dir;
  const engine::ArrayGeometry array = formats::LoadArray("3a-cg");
  const formats::ChannelMap map = formats::LoadChannelMap("default");
  fs::create_directories(dir / "csv");
  fs::create_directories(dir / "isomme");
  fs::create_directories(dir / "uds");
  double dt_s = 0.0;
  for (const NhtsaReference& reference : kReference) {
    const std::string test = reference.test;
    const Recording recording = ReadRecording(data / (test + ".csv"));
    ASSERT_EQ(recording.signals.size(), 3500) << test;
    dt_s = recording.signals.dt_s;
    WriteNapkinCsv(recording, dir / "csv" / (test + "-csv.csv"));
    formats::WriteIsoMme(recording.signals, array, map, dir / "isomme" / (test + "-isomme"), test);
    WriteUdsFiles(recording, dir / "uds", test + "-uds");
  }
  ASSERT_NEAR(dt_s, 1e-4, 1e-12);

  ASSERT_EQ(RunNapkin(dir.path(), {"init"}).exit_code, 0);
  // No channel map: ISO-MME and UDS-1992 channels are found by the default
  // map (codes, SENATT/AXIS), the CSV columns by slot name.
  for (const std::string format : {"csv", "isomme", "uds"}) {
    const std::vector<std::string> args = {"import", "--array",   "3a-cg", "--series",
                                           "nhtsa",  "--variant", format,  format};
    const RunResult import = RunNapkin(dir.path(), args);
    ASSERT_EQ(import.exit_code, 0) << format << ": " << import.err;
    EXPECT_NE(import.out.find("imported 3 tests"), std::string::npos) << import.out;
  }
  // The default config is what NHTSA ran: bias "auto" subtracts the mean of
  // every sample before t = 0 (RmBias over all t < 0; the recordings have
  // 50 ms of them), SAE J211 CFC 1000 on the linear channels (BWFilt at its
  // design frequency), HIC over all samples.
  const RunResult run = RunNapkin(dir.path(), {"run"});
  ASSERT_EQ(run.exit_code, 0) << run.err;

  const RunResult hic = RunNapkin(dir.path(), {"query", "hic", "--format", "json"});
  ASSERT_EQ(hic.exit_code, 0) << hic.err;
  // Keyed by the input's name (a catalogue that suffixes the dummy position,
  // "corolla-isomme/11", still names one test per input).
  std::map<std::string, nlohmann::json> rows;
  for (const nlohmann::json& row : nlohmann::json::parse(hic.out)) {
    const std::string id = row.at("test_id").get<std::string>();
    rows[id.substr(0, id.find('/'))] = row;
  }
  ASSERT_EQ(rows.size(), 9u) << hic.out;
  for (const NhtsaReference& reference : kReference) {
    for (const char* format : {"csv", "isomme", "uds"}) {
      const std::string id = std::string(reference.test) + "-" + format;
      SCOPED_TRACE(id);
      ASSERT_TRUE(rows.count(id)) << hic.out;
      const nlohmann::json& row = rows.at(id);
      ExpectRelative(row.at("hic15").get<double>(), reference.hic15, 1e-5, "hic15");
      ExpectSameSample(row.at("hic15_t1_s").get<double>(), reference.hic15_t1_ms, dt_s, "hic15 t1");
      ExpectSameSample(row.at("hic15_t2_s").get<double>(), reference.hic15_t2_ms, dt_s, "hic15 t2");
      ExpectRelative(row.at("hic36").get<double>(), reference.hic36, 1e-5, "hic36");
      ExpectSameSample(row.at("hic36_t1_s").get<double>(), reference.hic36_t1_ms, dt_s, "hic36 t1");
      ExpectSameSample(row.at("hic36_t2_s").get<double>(), reference.hic36_t2_ms, dt_s, "hic36 t2");
      ExpectRelative(row.at("hic").get<double>(), reference.hic, 1e-5, "hic");
      ExpectSameSample(row.at("hic_t1_s").get<double>(), reference.hic_t1_ms, dt_s, "hic t1");
      ExpectSameSample(row.at("hic_t2_s").get<double>(), reference.hic_t2_ms, dt_s, "hic t2");
      ExpectRelative(row.at("peak_acc_g").get<double>(), reference.peak_g, 1e-4, "peak_acc_g");
      ExpectRelative(row.at("a3ms_g").get<double>(), reference.a3ms_g, 1e-4, "a3ms_g");
      ExpectRelative(row.at("hic_d").get<double>(), 0.75446 * reference.hic36 + 166.4, 1e-5, "hic_d");
    }
  }

  // No rotation: every rotation field is null, and each test has the one
  // info finding that says why.
  const RunResult rotation = RunNapkin(dir.path(), {"query", "rotation", "--format", "json"});
  ASSERT_EQ(rotation.exit_code, 0) << rotation.err;
  const nlohmann::json rotation_rows = nlohmann::json::parse(rotation.out);
  ASSERT_EQ(rotation_rows.size(), 9u);
  for (const nlohmann::json& row : rotation_rows)
    for (const auto& [key, value] : row.items())
      if (key != "test_id" && key != "series" && key != "variant") {
        EXPECT_TRUE(value.is_null()) << key;
      }
  const RunResult quality = RunNapkin(dir.path(), {"query", "quality", "--format", "json"});
  ASSERT_EQ(quality.exit_code, 0) << quality.err;
  std::map<std::string, int> rotation_findings;
  for (const nlohmann::json& finding : nlohmann::json::parse(quality.out)) {
    EXPECT_NE(finding.at("severity"), "error") << finding.dump();
    if (finding.at("check") == "rotation") ++rotation_findings[finding.at("test_id").get<std::string>()];
  }
  EXPECT_EQ(rotation_findings.size(), 9u);

  // The report of the three variants: the acceleration overlay only (a
  // trace per test, two corridor bounds per variant), no rotation chart, and
  // no compare row of a metric no test has (docs/formats.md "Overlaid curves").
  const RunResult report =
      RunNapkin(dir.path(), {"report", "--series", "nhtsa", "--align", "onset", "--out", "nhtsa.html"});
  ASSERT_EQ(report.exit_code, 0) << report.err;
  std::ifstream in(dir / "nhtsa.html");
  const std::string html((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string marker = "<script type=\"application/json\" id=\"napkin-data\">";
  const std::size_t begin = html.find(marker);
  ASSERT_NE(begin, std::string::npos);
  const nlohmann::json plot_data = nlohmann::json::parse(
      html.substr(begin + marker.size(), html.find("</script>", begin) - begin - marker.size()));
  ASSERT_EQ(plot_data.at("overlays").size(), 1u);
  EXPECT_EQ(plot_data.at("overlays")[0].at("id"), "overlay-1-acc");
  EXPECT_EQ(plot_data.at("overlays")[0].at("labels").size(), 9u + 3u * 2u);
  EXPECT_EQ(html.find("overlay-1-omega"), std::string::npos);
  for (const char* rotation_metric :
       {"peak_omega_radps", "peak_alpha_radps2", "bric", "damage", "max_rotation_deg"})
    EXPECT_EQ(html.find(std::string("<tr><td>") + rotation_metric + "</td>"), std::string::npos)
        << rotation_metric;
  EXPECT_NE(html.find("<tr><td>hic15</td>"), std::string::npos);

  // CLI compare with the default metrics prints no n = 0 block (issue 30
  // point 5): the rotation metrics no test has are left out, in every format;
  // a metric named in --metrics is still shown.
  const RunResult compare = RunNapkin(dir.path(), {"compare", "--series", "nhtsa"});
  ASSERT_EQ(compare.exit_code, 0) << compare.err;
  for (const std::string& line : Lines(compare.out)) {
    std::istringstream cells(line);
    std::string group, n;
    cells >> group >> n;
    EXPECT_NE(n, "0") << line << "\n" << compare.out;
  }
  for (const char* rotation_metric : {"peak_omega_radps", "peak_alpha_radps2", "bric", "damage",
                                      "max_rotation_deg", "bric_p_ais3", "bric_p_ais4"}) {
    EXPECT_EQ(compare.out.find(std::string("\n") + rotation_metric + "\n"), std::string::npos)
        << rotation_metric;
    EXPECT_EQ(compare.out.find(std::string("\n") + rotation_metric + " ("), std::string::npos)
        << rotation_metric;
  }
  EXPECT_NE(compare.out.find("\nhic15 (log scale"), std::string::npos) << compare.out;
  const RunResult json = RunNapkin(dir.path(), {"compare", "--series", "nhtsa", "--format", "json"});
  ASSERT_EQ(json.exit_code, 0) << json.err;
  for (const nlohmann::json& row : nlohmann::json::parse(json.out)) EXPECT_NE(row.at("n"), 0) << row.dump();
  const RunResult named =
      RunNapkin(dir.path(), {"compare", "--series", "nhtsa", "--metrics", "hic15,bric", "--format", "json"});
  ASSERT_EQ(named.exit_code, 0) << named.err;
  EXPECT_EQ(nlohmann::json::parse(named.out).size(), 6u);
}

}  // namespace
}  // namespace napkin::cli
