#include "formats/csv.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include "engine/units.h"
#include "tests/formats/formats_test_util.h"
#include "tests/support/named_cases.h"
#include "tests/support/reference_arrays.h"
#include "tests/support/test_support.h"
#include "util/text.h"

namespace napkin::formats {
namespace {

using test_support::ExpectInputError;
using test_support::MakeSignals;
using test_support::TempDir;
using test_support::WriteBytes;

TEST(CsvTest, RawSignalsRoundTripToIdenticalSamples) {
  TempDir dir;
  const engine::ArrayGeometry array = test_support::NapArs12();
  const engine::TestSignals written = MakeSignals(array, 1234, 1e-4, -0.01);
  WriteSignalsCsv(written, dir / "raw.csv");
  const CsvSignals read = ReadSignalsCsv(dir / "raw.csv", &array);
  EXPECT_TRUE(read.warnings.empty());
  EXPECT_EQ(read.signals.slots, written.slots);
  ASSERT_EQ(read.signals.samples.rows(), written.samples.rows());
  EXPECT_TRUE((read.signals.samples.array() == written.samples.array()).all());
  EXPECT_EQ(read.signals.t0_s, written.t0_s);
  EXPECT_NEAR(read.signals.dt_s, written.dt_s, 1e-15 * written.dt_s + 1e-19);
}

TEST(CsvTest, ColumnsInAnyOrderCommentsCrlfAndExtraColumns) {
  TempDir dir;
  const engine::ArrayGeometry array = test_support::SixAOmegaCg();
  // Slots shuffled, an extra column, comment lines, CRLF, blanks around values.
  WriteBytes(dir / "in.csv",
             "# a comment\r\n"
             "ars_z,time_s,cg_y,extra,cg_x,ars_x,cg_z,ars_y\r\n"
             "# another\r\n"
             " 6, 0.000 ,2,99,1,4,3,5\r\n"
             "16,0.001,12,99,11,14,13,15\r\n"
             "26,0.002,22,99,21,24,23,+25\r\n");
  const CsvSignals read = ReadSignalsCsv(dir / "in.csv", &array);
  ASSERT_EQ(read.warnings.size(), 1u);
  EXPECT_NE(read.warnings[0].find("\"extra\""), std::string::npos);
  EXPECT_EQ(read.signals.slots,
            (std::vector<std::string>{"cg_x", "cg_y", "cg_z", "ars_x", "ars_y", "ars_z"}));
  ASSERT_EQ(read.signals.size(), 3);
  for (int k = 0; k < 3; ++k)
    for (int c = 0; c < 6; ++c) EXPECT_EQ(read.signals.samples(k, c), 10.0 * k + c + 1);
  EXPECT_DOUBLE_EQ(read.signals.dt_s, 0.001);
  EXPECT_EQ(read.signals.t0_s, 0.0);
  // Each sample's file line, comment lines counted (issue 29 point 11).
  EXPECT_EQ(read.signals.file_rows, (std::vector<std::int64_t>{4, 5, 6}));
  EXPECT_EQ(read.signals.FileRowOf(2), 6);
  EXPECT_FALSE(read.signals.FileRowOf(3));
}

TEST(CsvTest, WithoutArrayEveryColumnInFileOrder) {
  TempDir dir;
  WriteBytes(dir / "in.csv", "b,time_s,a\n1,0,2\n3,0.5,4\n");
  const CsvSignals read = ReadSignalsCsv(dir / "in.csv");
  EXPECT_EQ(read.signals.slots, (std::vector<std::string>{"b", "a"}));
  EXPECT_EQ(read.signals.samples(1, 1), 4.0);
  EXPECT_EQ(read.signals.dt_s, 0.5);
}

TEST(CsvTest, JitterWithinOnePpmIsAccepted) {
  TempDir dir;
  std::ostringstream text;
  text << "time_s,a\n";
  for (int k = 0; k < 100; ++k)
    text << util::FormatNumber(k * 1e-4 * (1.0 + ((k % 2) ? 4e-7 / k : 0.0))) << "," << k << "\n";
  WriteBytes(dir / "in.csv", text.str());
  EXPECT_NO_THROW(ReadSignalsCsv(dir / "in.csv"));
}

// A CSV file the reader refuses, and what the message must mention besides
// the file: the row, the column or the problem.
struct CsvErrorCase {
  const char* name;  // also the file's stem
  std::string text;
  std::vector<std::string> fragments;
};
void PrintTo(const CsvErrorCase& error, std::ostream* os) { *os << error.name << ".csv"; }

const std::string kHeader = "time_s,cg_x,cg_y,cg_z,ars_x,ars_y,ars_z\n";

class CsvErrorTest : public ::testing::TestWithParam<CsvErrorCase> {};

TEST_P(CsvErrorTest, NamesFileRowAndColumn) {
  TempDir dir;
  const engine::ArrayGeometry array = test_support::SixAOmegaCg();
  const std::filesystem::path path = dir / (std::string(GetParam().name) + ".csv");
  WriteBytes(path, GetParam().text);
  std::vector<std::string> fragments = GetParam().fragments;
  fragments.insert(fragments.begin(), path.string());
  ExpectInputError([&] { ReadSignalsCsv(path, &array); }, fragments);
}

INSTANTIATE_TEST_SUITE_P(
    BadFiles, CsvErrorTest,
    ::testing::Values(
        CsvErrorCase{"empty_value",
                     kHeader + "0,1,2,3,4,5,6\n0.1,1,,3,4,5,6\n",
                     {"row 3", "column \"cg_y\" is empty"}},
        CsvErrorCase{"nan",
                     kHeader + "0,1,2,3,4,5,6\n0.1,1,2,nan,4,5,6\n",
                     {"row 3", "column \"cg_z\"", "not a finite number"}},
        CsvErrorCase{"text",
                     kHeader + "# c\n0,1,2,3,4,abc,6\n0.1,1,2,3,4,5,6\n",
                     {"row 3", "column \"ars_y\"", "\"abc\" is not a number"}},
        CsvErrorCase{
            "short_row", kHeader + "0,1,2,3,4,5,6\n0.1,1,2,3\n", {"row 3 has 4 values", "7 columns"}},
        CsvErrorCase{"missing_slot",
                     "time_s,cg_x,cg_y,cg_z,ars_x,ars_y\n0,1,2,3,4,5\n0.1,1,2,3,4,5\n",
                     {"no column for slot \"ars_z\""}},
        CsvErrorCase{"no_time", "t,cg_x,cg_y,cg_z,ars_x,ars_y,ars_z\n0,1,2,3,4,5,6\n", {"no time_s column"}},
        CsvErrorCase{"decreasing",
                     kHeader + "0,1,2,3,4,5,6\n0.1,1,2,3,4,5,6\n0.1,1,2,3,4,5,6\n0.3,1,2,3,4,5,6\n",
                     {"row 4", "does not increase"}},
        CsvErrorCase{
            "jitter",
            kHeader +
                "0,1,2,3,4,5,6\n0.1,1,2,3,4,5,6\n0.2001,1,2,3,4,5,6\n0.3,1,2,3,4,5,6\n0.4,1,2,3,4,5,6\n",
            {"row 4", "uniformly spaced"}},
        CsvErrorCase{"one_row", kHeader + "0,1,2,3,4,5,6\n", {"1 data row", "at least two"}},
        CsvErrorCase{"no_header", "# only comments\n", {"no header"}},
        CsvErrorCase{"dup", "time_s,cg_x,cg_x\n", {"names column \"cg_x\" twice"}}),
    test_support::CaseName());

TEST(CsvTest, MissingFileIsNamed) {
  TempDir dir;
  const engine::ArrayGeometry array = test_support::SixAOmegaCg();
  ExpectInputError([&] { ReadSignalsCsv(dir / "absent.csv", &array); },
                   {(dir / "absent.csv").string(), "cannot open"});
}

engine::Kinematics MakeKinematics(Eigen::Index n) {
  engine::Kinematics k;
  k.Resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    k.time_s[i] = 0.001 * static_cast<double>(i);
    for (int c = 0; c < 3; ++c) {
      const double base = static_cast<double>(i) + 0.1 * c;
      k.omega_body(i, c) = base + 1;
      k.alpha_body(i, c) = base + 2;
      k.omega_fixed(i, c) = base + 3;
      k.alpha_fixed(i, c) = base + 4;
      k.acc_body(i, c) = (base + 5) * engine::kStandardGravity;
      k.acc_fixed(i, c) = (base + 6) * engine::kStandardGravity;
      k.vel_fixed(i, c) = base + 7;
      k.pos_fixed(i, c) = base + 8;
      k.roll_pitch_yaw_rad(i, c) = (base + 9) / engine::kDegPerRad;
      k.dcos_rad(i, c) = (base + 10) / engine::kDegPerRad;
    }
    k.quat_fixed_from_body.row(i) << 0.5, -0.5, 0.5, -0.5 + 1e-9 * static_cast<double>(i);
  }
  return k;
}

TEST(CsvTest, DerivedHeaderIsTheContract) {
  TempDir dir;
  WriteDerivedCsv(MakeKinematics(3), dir / "derived.csv");
  const std::string text = test_support::ReadBytes(dir / "derived.csv");
  const std::string expected_header =
      "time_s,omega_body_x_radps,omega_body_y_radps,omega_body_z_radps,"
      "alpha_body_x_radps2,alpha_body_y_radps2,alpha_body_z_radps2,"
      "omega_fixed_x_radps,omega_fixed_y_radps,omega_fixed_z_radps,"
      "alpha_fixed_x_radps2,alpha_fixed_y_radps2,alpha_fixed_z_radps2,"
      "acc_body_x_g,acc_body_y_g,acc_body_z_g,acc_fixed_x_g,acc_fixed_y_g,acc_fixed_z_g,"
      "vel_fixed_x_mps,vel_fixed_y_mps,vel_fixed_z_mps,pos_fixed_x_m,pos_fixed_y_m,pos_fixed_z_m,"
      "quat_w,quat_x,quat_y,quat_z,roll_deg,pitch_deg,yaw_deg,dcos_xx_deg,dcos_yy_deg,dcos_zz_deg";
  EXPECT_EQ(text.substr(0, text.find('\n')), expected_header);
}

TEST(CsvTest, DerivedValuesInContractUnitsWithNineDigits) {
  TempDir dir;
  const engine::Kinematics k = MakeKinematics(50);
  WriteDerivedCsv(k, dir / "derived.csv");
  const CsvSignals read = ReadSignalsCsv(dir / "derived.csv");
  ASSERT_EQ(read.signals.samples.cols(), 34);
  ASSERT_EQ(read.signals.size(), 50);
  for (Eigen::Index i = 0; i < 50; ++i) {
    for (int c = 0; c < 3; ++c) {
      const double base = static_cast<double>(i) + 0.1 * c;
      // Columns after time_s: omega_body(0..2), alpha_body, omega_fixed, alpha_fixed, acc_body (g), acc_fixed
      // (g), vel, pos, quat(4), rpy (deg), dcos (deg); each equals base + its group number by construction.
      for (int group = 0; group < 8; ++group)
        EXPECT_NEAR(read.signals.samples(i, group * 3 + c), base + group + 1, 1e-9 * (base + group + 1));
      EXPECT_NEAR(read.signals.samples(i, 28 + c), base + 9, 1e-9 * (base + 9));
      EXPECT_NEAR(read.signals.samples(i, 31 + c), base + 10, 1e-9 * (base + 10));
    }
    EXPECT_NEAR(read.signals.samples(i, 27), -0.5 + 1e-9 * static_cast<double>(i), 1e-12);
  }
}

TEST(CsvTest, WriterLeavesNoPartialFileBehind) {
  TempDir dir;
  engine::TestSignals bad;
  bad.slots = {"a", "b"};
  bad.samples.resize(3, 1);  // slots do not match columns
  EXPECT_THROW(WriteSignalsCsv(bad, dir / "out.csv"), InputError);
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
  EXPECT_THROW(
      WriteSignalsCsv(MakeSignals(test_support::Ideal3222(), 3, 1e-3, 0), dir / "missing-dir" / "out.csv"),
      InputError);
}

}  // namespace
}  // namespace napkin::formats
