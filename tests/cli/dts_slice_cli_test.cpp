// DTS SLICEWare CSV exports end to end (issue 46 acceptance): exports written
// from the synthetic truth in SLICEWare's layout (tests/support/
// dts_slice_writer.h) through `napkin transform` and `napkin import` as a lab
// gets them: a 6DX headform (head CG accelerometers and angular-rate sensors)
// with and without --array, its Test ID as the test id, the software filter
// respected, and a 3-2-2-2 head exported with its arms' codes equal to the
// same samples in napkin's CSV.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/transform.h"
#include "formats/csv.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/dts_slice_writer.h"
#include "tests/support/test_support.h"

namespace napkin::test_support {
namespace {

// The columns of a CSV file napkin wrote (transform --out), by name.
std::map<std::string, std::vector<double>> CsvColumns(const fs::path& path) {
  std::istringstream in(ReadText(path));
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::istringstream header(line);
  for (std::string name; std::getline(header, name, ',');) names.push_back(name);
  std::map<std::string, std::vector<double>> columns;
  while (std::getline(in, line)) {
    std::istringstream cells(line);
    std::string cell;
    for (std::size_t c = 0; c < names.size() && std::getline(cells, cell, ','); ++c)
      if (!cell.empty()) columns[names[c]].push_back(std::stod(cell));
  }
  return columns;
}

// The largest difference of the derived angular velocity from the truth, as a fraction of its peak.
double OmegaErrorOfPeak(const fs::path& derived, const synth::SyntheticTest& truth) {
  const std::map<std::string, std::vector<double>> columns = CsvColumns(derived);
  const char* names[3] = {"omega_body_x_radps", "omega_body_y_radps", "omega_body_z_radps"};
  double peak = 0.0, error = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    const std::vector<double>& omega = columns.at(names[axis]);
    EXPECT_EQ(omega.size(), static_cast<std::size_t>(truth.truth.omega_body.rows()));
    for (std::size_t k = 0; k < omega.size(); ++k) {
      const double exact = truth.truth.omega_body(static_cast<Eigen::Index>(k), axis);
      peak = std::max(peak, std::abs(exact));
      error = std::max(error, std::abs(omega[k] - exact));
    }
  }
  return error / peak;
}

class DtsSliceCli : public ::testing::Test {
 protected:
  void SetUp() override {
    synth::RandomMotionOptions motion;
    motion.seed = 46;
    motion.duration_s = 0.04;
    motion.synth.rate_hz = 20000.0;
    six_dx_ = synth::SynthRandomMotion(formats::LoadArray("6aw-cg"), motion);
    dts_ = SixDxExport(six_dx_.signals, six_dx_.array);
    WriteDtsExport(dts_, dir_ / "2024-05-23-c-fh1_UNFILTERED.csv");
    // The samples as recorded: no filter, no bias, so the output is the truth's motion.
    WriteText(dir_ / "as-recorded.json",
              R"({"name": "as-recorded", "filter": {"linear_cfc": "none", "angular_rate_cfc": "none"},
                  "bias": {"mode": "none"}})");
  }

  RunResult Transform(const std::string& input, const std::string& out, std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"transform",
                                     input,
                                     "--out",
                                     out,
                                     "--summary",
                                     out + ".json",
                                     TripleFlag("--orientation", six_dx_.initial.orientation_rad),
                                     TripleFlag("--initial-velocity", six_dx_.initial.velocity_fixed_mps)};
    args.insert(args.end(), extra.begin(), extra.end());
    return RunNapkin(dir_.path(), args);
  }

  TempDir dir_;
  synth::SyntheticTest six_dx_;
  DtsExport dts_;
};

TEST_F(DtsSliceCli, SixDxExportTransformsToTheTruthWithAndWithoutArray) {
  const std::string input = "2024-05-23-c-fh1_UNFILTERED.csv";
  const RunResult from_codes = Transform(input, "codes.csv", {"--config", "as-recorded.json"});
  ASSERT_EQ(from_codes.exit_code, 0) << from_codes.err;
  const RunResult given =
      Transform(input, "given.csv", {"--config", "as-recorded.json", "--array", "6aw-cg"});
  ASSERT_EQ(given.exit_code, 0) << given.err;
  const double error = OmegaErrorOfPeak(dir_ / "codes.csv", six_dx_);
  EXPECT_LT(error, 5e-4);
  RecordProperty("omega_error_of_peak", util::FormatNumber(error, 3));
  // The codes define the array the option names: the same bytes.
  EXPECT_EQ(ReadText(dir_ / "codes.csv"), ReadText(dir_ / "given.csv"));
  const nlohmann::json summary = nlohmann::json::parse(ReadText(dir_ / "codes.csv.json"));
  EXPECT_EQ(summary.at("test_id"), "DTS-1");  // the export's Test ID, not its file name
  EXPECT_EQ(ReadText(dir_ / "codes.csv.json"), ReadText(dir_ / "given.csv.json"));
}

// `Software Filter (SAE Class)` as ISO-MME's filter letter: a channel SLICEWare filtered is not
// filtered again (docs/algorithms.md "Signal conditioning"); one it did not filter is.
TEST_F(DtsSliceCli, SoftwareFilteredChannelsAreNotFilteredAgain) {
  for (std::size_t c = 0; c < 3; ++c) dts_.channels[c].software_filter = "60";    // AV: CFC 60
  for (std::size_t c = 3; c < 6; ++c) dts_.channels[c].software_filter = "1000";  // AC: CFC 1000
  WriteDtsExport(dts_, dir_ / "filtered.csv");
  const RunResult filtered = Transform("filtered.csv", "filtered-out.csv", {"--config", "default"});
  ASSERT_EQ(filtered.exit_code, 0) << filtered.err;
  const RunResult raw = Transform("2024-05-23-c-fh1_UNFILTERED.csv", "raw-out.csv", {"--config", "default"});
  ASSERT_EQ(raw.exit_code, 0) << raw.err;
  const double prefiltered_error = OmegaErrorOfPeak(dir_ / "filtered-out.csv", six_dx_);
  const double refiltered_error = OmegaErrorOfPeak(dir_ / "raw-out.csv", six_dx_);
  EXPECT_LT(prefiltered_error, 5e-4);                     // the default config's CFC 60 was not applied again
  EXPECT_GT(refiltered_error, 10.0 * prefiltered_error);  // and it was applied to the raw channels
  RecordProperty("refiltered_error_of_peak", util::FormatNumber(refiltered_error, 3));
  RecordProperty("prefiltered_error_of_peak", util::FormatNumber(prefiltered_error, 3));
  const nlohmann::json summary = nlohmann::json::parse(ReadText(dir_ / "filtered-out.csv.json"));
  for (const nlohmann::json& channel : summary.at("conditioning")) {
    if (channel.at("channel") == "ars_x") {
      EXPECT_EQ(channel.at("filter"), "none, prefiltered at CFC 60");
    }
  }
}

TEST_F(DtsSliceCli, ImportsWithItsTestIdAndItsSensorsAsTestInformation) {
  ASSERT_EQ(RunNapkin(dir_.path(), {"init"}).exit_code, 0);
  const RunResult imported =
      RunNapkin(dir_.path(), {"import", "2024-05-23-c-fh1_UNFILTERED.csv", "--series", "drop",
                              TripleFlag("--orientation", six_dx_.initial.orientation_rad),
                              TripleFlag("--initial-velocity", six_dx_.initial.velocity_fixed_mps)});
  ASSERT_EQ(imported.exit_code, 0) << imported.err;
  EXPECT_NE(imported.out.find("imported 1 test"), std::string::npos) << imported.out;
  {
    db::Catalogue catalogue = OpenForReading(dir_ / "napkin.db");
    const std::optional<db::TestId> id = catalogue.FindTestByExternalId("DTS-1");
    ASSERT_TRUE(id);
    const nlohmann::json metadata = nlohmann::json::parse(catalogue.ReadTest(*id).metadata_json);
    EXPECT_EQ(metadata.at("format"), "dts-slice-csv");
    EXPECT_EQ(metadata.at("array_from_codes"), true);
    EXPECT_EQ(metadata.at("channel_map"), "default");
    const nlohmann::json& test = metadata.at("test");
    EXPECT_EQ(test.at("test_number"), "DTS-1");
    EXPECT_EQ(test.at("title"), "synthetic head impact");
    EXPECT_EQ(test.at("position"), "D0");
    ASSERT_EQ(test.at("sensors").size(), 6u);
    EXPECT_EQ(test.at("sensors")[0], nlohmann::json::parse(R"({"slot": "cg_x", "code": "D0HEADCG0000ACXA",
                                                               "serial": "6DX0855-AC1",
                                                               "hardware_filter_hz": 4300})"));
  }
  const RunResult tests = RunNapkin(dir_.path(), {"query", "tests", "--format", "json"});
  ASSERT_EQ(tests.exit_code, 0) << tests.err;
  const nlohmann::json rows = nlohmann::json::parse(tests.out);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].at("test_id"), "DTS-1");
  EXPECT_EQ(rows[0].at("array"), "6aw-cg");
  // The same content again: skipped under its Test ID.
  const RunResult again = RunNapkin(dir_.path(), {"import", "2024-05-23-c-fh1_UNFILTERED.csv"});
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.out.find("DTS-1: already imported (same content), skipped."), std::string::npos)
      << again.out;

  // The catalogue's result is the transform's.
  ASSERT_EQ(RunNapkin(dir_.path(), {"run"}).exit_code, 0);
  const RunResult criteria = RunNapkin(dir_.path(), {"query", "criteria", "--format", "json"});
  ASSERT_EQ(Transform("2024-05-23-c-fh1_UNFILTERED.csv", "t.csv").exit_code, 0);
  const nlohmann::json summary = nlohmann::json::parse(ReadText(dir_ / "t.csv.json"));
  const nlohmann::json row = nlohmann::json::parse(criteria.out).at(0);
  for (const char* field : {"hic15", "peak_acc_g", "peak_omega_radps", "bric"})
    EXPECT_EQ(row.at(field), summary.at(field)) << field;
}

TEST_F(DtsSliceCli, ABadExportIsOneSentenceAndNothingIsWritten) {
  dts_.channels[3].unit = "gee ";
  WriteDtsExport(dts_, dir_ / "bad.csv");
  const RunResult transform = Transform("bad.csv", "bad-out.csv");
  EXPECT_EQ(transform.exit_code, 1);
  ExpectOneSentenceError(transform,
                         {"bad.csv: row 15 (\"Engineering Unit\")",
                          "channel \"Chan 3:6DX0855-AC3\" (D0HEADCG0000ACZA)", "unrecognised unit \"gee\""});
  EXPECT_FALSE(fs::exists(dir_ / "bad-out.csv"));
  ASSERT_EQ(RunNapkin(dir_.path(), {"init"}).exit_code, 0);
  const RunResult imported = RunNapkin(dir_.path(), {"import", "bad.csv"});
  EXPECT_EQ(imported.exit_code, 1);
  EXPECT_NE(imported.err.find("unrecognised unit \"gee\""), std::string::npos) << imported.err;
}

// A 3-2-2-2 head exported with its arms' codes (the lab convention of the nap-example map: fine
// locations CG, RI, FR, BO): its geometry is the array's, so it is given; then the export reads to
// exactly the samples napkin's CSV of the same test reads to.
TEST_F(DtsSliceCli, NineAccelerometerExportEqualsTheSameSamplesInNapkinsCsv) {
  const synth::SyntheticTest nap = SynthNapTest(4646);
  const std::map<std::string, std::string> code_of_slot = {
      {"cg_x", "D0HEADCG0000ACXA"},   {"cg_y", "D0HEADCG0000ACYA"},   {"cg_z", "D0HEADCG0000ACZA"},
      {"yarm_z", "D0HEADRI0000ACZA"}, {"yarm_x", "D0HEADRI0000ACXA"}, {"xarm_z", "D0HEADFR0000ACZA"},
      {"xarm_y", "D0HEADFR0000ACYA"}, {"zarm_x", "D0HEADBO0000ACXA"}, {"zarm_y", "D0HEADBO0000ACYA"}};
  DtsExport dts;
  dts.test_id = "NAP-1";
  dts.sample_rate_hz = std::round(1.0 / nap.signals.dt_s);
  dts.t0_s = nap.signals.t0_s;
  // Channels in another order than the array's: the codes place them.
  for (std::size_t s = nap.array.sensors.size(); s-- > 0;) {
    DtsChannel channel;
    channel.code = code_of_slot.at(nap.array.sensors[s].slot);
    channel.serial = "7264C-" + std::to_string(1000 + s);
    for (Eigen::Index k = 0; k < nap.signals.samples.rows(); ++k)
      channel.values.push_back(nap.signals.samples(k, static_cast<Eigen::Index>(s)));
    dts.channels.push_back(std::move(channel));
  }
  WriteDtsExport(dts, dir_ / "nap.csv");
  formats::WriteSignalsCsv(nap.signals, dir_ / "nap-napkin.csv");

  app::TestFileOptions read;
  read.path = (dir_ / "nap.csv").string();
  read.array = "denton-3222";
  read.channel_map = "nap-example";
  const app::TestFile from_dts = app::ReadTestFile(read);
  read.path = (dir_ / "nap-napkin.csv").string();
  read.channel_map.clear();
  const app::TestFile from_csv = app::ReadTestFile(read);
  EXPECT_EQ(from_dts.test_id, "NAP-1");
  EXPECT_EQ(from_dts.signals.slots, from_csv.signals.slots);
  ASSERT_EQ(from_dts.signals.samples.rows(), from_csv.signals.samples.rows());
  std::size_t differing = 0;
  for (Eigen::Index k = 0; k < from_csv.signals.samples.rows(); ++k)
    for (Eigen::Index c = 0; c < from_csv.signals.samples.cols(); ++c)
      differing += std::bit_cast<std::uint64_t>(from_dts.signals.samples(k, c)) !=
                   std::bit_cast<std::uint64_t>(from_csv.signals.samples(k, c));
  EXPECT_EQ(differing, 0u);  // bit for bit
  EXPECT_EQ(from_dts.signals.t0_s, from_csv.signals.t0_s);
  // The export's rate against the CSV's mean step over its time column: the same to the last bits.
  EXPECT_NEAR(from_dts.signals.dt_s, from_csv.signals.dt_s, 1e-15 * from_csv.signals.dt_s);

  // Without the array the arms' sentence says what is missing; without the map, which slot.
  const RunResult no_array = RunNapkin(dir_.path(), {"transform", "nap.csv", "--out", "n.csv"});
  EXPECT_EQ(no_array.exit_code, 2);  // the array must be given: a usage error, as a missing --array was
  ExpectOneSentenceError(no_array,
                         {"test NAP-1", "channel D0HEADBO0000ACYA", "off the CG (fine location \"BO\")",
                          "an array with arms needs its geometry", "--array"});
  const RunResult no_map =
      RunNapkin(dir_.path(), {"transform", "nap.csv", "--array", "denton-3222", "--out", "n.csv"});
  EXPECT_EQ(no_map.exit_code, 1);
  ExpectOneSentenceError(no_map, {"channel map \"default\"", "slot \"yarm_z\""});
  const RunResult given = RunNapkin(dir_.path(), {"transform", "nap.csv", "--array", "denton-3222",
                                                  "--channel-map", "nap-example", "--out", "n.csv"});
  EXPECT_EQ(given.exit_code, 0) << given.err;
}

}  // namespace
}  // namespace napkin::test_support
