// Model curves (formats/model_curves.h): the nodout fixture of
// tests/fixtures/iso18571/make_nodout.py in two unit systems, the model CSV,
// napkin's own LS-DYNA export read back and rated against its test (ISO/TS
// 18571: 1.000), a displaced array and CFC 180 rated below, and every error
// as one sentence naming the file and line.
#include "formats/model_curves.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>

#include "common/error.h"
#include "engine/iso18571.h"
#include "engine/pipeline.h"
#include "formats/lsdyna.h"
#include "synth/synthetic_tests.h"
#include "tests/support/reference_arrays.h"
#include "tests/support/test_support.h"
#include "util/sha256.h"

namespace napkin::formats {
namespace {

using test_support::TempDir;

const std::filesystem::path kNodout =
    std::filesystem::path(NAPKIN_FIXTURES_DIR) / "iso18571" / "nodout_mm_ms";

const ModelCurve& Named(const std::vector<ModelCurve>& curves, const std::string& name) {
  for (const ModelCurve& curve : curves)
    if (curve.name == name) return curve;
  throw std::runtime_error("no curve " + name);
}

template <typename F>
std::string ModelErrorOf(F&& f) {
  try {
    f();
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

void WriteText(const std::filesystem::path& path, const std::string& text) { std::ofstream(path) << text; }

TEST(ModelUnits, ParsesLengthTimeMass) {
  const ModelUnits mm = ParseModelUnits("mm,ms,kg");
  EXPECT_EQ(mm.metres, 1e-3);
  EXPECT_EQ(mm.seconds, 1e-3);
  EXPECT_EQ(mm.kilograms, 1.0);
  // 1 mm/ms^2 = 1000 m/s^2; 1 mm/ms = 1 m/s; 1 / ms = 1000 / s.
  EXPECT_NEAR(SiPerUnit(mm, kAccelerationDimension), 1000.0, 1e-9);
  EXPECT_NEAR(SiPerUnit(mm, kVelocityDimension), 1.0, 1e-15);
  EXPECT_NEAR(SiPerUnit(mm, kAngularVelocityDimension), 1000.0, 1e-9);
  const ModelUnits si = ParseModelUnits(" M , S , KG ");
  EXPECT_EQ(SiPerUnit(si, kAccelerationDimension), 1.0);
  EXPECT_NEAR(SiPerUnit(ParseModelUnits("in,s,lbf-s2/in"), kAccelerationDimension), 0.0254, 1e-15);
  try {
    ParseModelUnits("mm,ms");
    FAIL();
  } catch (const UsageError& error) {
    EXPECT_STREQ(
        error.what(),
        "--model-units 'mm,ms' is not LENGTH,TIME,MASS with a length of m, cm, mm, in or ft, a time of s, "
        "ms or us and a mass of kg, g, t or lbf-s2/in (e.g. mm,ms,kg).");
  }
  EXPECT_THROW(ParseModelUnits("mm,min,kg"), UsageError);
}

// The fixture in mm, ms, kg: 1 mm/ms^2 reads as 1000 m/s^2.
TEST(Nodout, FixtureInMillimetresAndMillisecondsReadsInSi) {
  const std::vector<ModelCurve> curves = ReadNodout(kNodout, ParseModelUnits("mm,ms,kg"));
  EXPECT_EQ(curves.size(), 2u * (12 + 9));
  const ModelCurve& accl = Named(curves, "node 7 x-accl");
  EXPECT_EQ(accl.dimension, kAccelerationDimension);
  ASSERT_EQ(accl.series.values.size(), 21);
  for (Eigen::Index k = 0; k < 21; ++k) {
    EXPECT_NEAR(accl.series.time_s(k), 0.5e-3 * static_cast<double>(k), 1e-15);
    EXPECT_NEAR(accl.series.values(k), 1000.0, 1e-9);
  }
  EXPECT_NEAR(Named(curves, "node 7 z-accl").series.values(20), -2000.0, 1e-9);
  EXPECT_NEAR(Named(curves, "node 7 x-vel").series.values(20), 10.0, 1e-12);   // 10 mm/ms = 10 m/s
  EXPECT_NEAR(Named(curves, "node 7 x-disp").series.values(20), 0.05, 1e-15);  // 50 mm
  EXPECT_NEAR(Named(curves, "node 1234 x-accl").series.values(3), 3000.0, 1e-9);
  EXPECT_NEAR(Named(curves, "node 1234 y-coor").series.values(3), -0.05, 1e-15);
  // The rotational block, whose fields touch.
  EXPECT_NEAR(Named(curves, "node 7 x-rot-vel").series.values(5), 10.0, 1e-12);
  EXPECT_NEAR(Named(curves, "node 7 x-rot-acc").series.values(5), 1000.0, 1e-9);
  EXPECT_NEAR(Named(curves, "node 7 y-rot-acc").series.values(5), -1000.0, 1e-9);
  EXPECT_NEAR(Named(curves, "node 7 z-rot-acc").series.values(5), -2000.0, 1e-9);
  EXPECT_NEAR(Named(curves, "node 7 x-rot").series.values(20), 0.1, 1e-15);
  EXPECT_EQ(Named(curves, "node 7 x-rot").dimension, kAngleDimension);
  // The same file taken as m, s, kg: the numbers as written.
  const std::vector<ModelCurve> raw = ReadNodout(kNodout, ParseModelUnits("m,s,kg"), 7);
  EXPECT_EQ(raw.size(), 12u + 9u);
  EXPECT_EQ(Named(raw, "node 7 x-accl").series.values(4), 1.0);
  EXPECT_EQ(Named(raw, "node 7 x-accl").series.time_s(20), 10.0);
  EXPECT_EQ(ModelErrorOf([] { ReadNodout(kNodout, ModelUnits{}, 99); }),
            kNodout.string() + " line 1: the nodout has no node 99 (its first block lists 7, 1234).");
}

TEST(Nodout, RefusesBadInputNamingFileAndLine) {
  TempDir dir;
  const auto path = dir / "nodout";
  const std::string header =
      " n o d a l   p r i n t   o u t   f o r   t i m e  s t e p       1  ( at time 0.00000E+00 )\n\n"
      " nodal point  x-disp     y-disp      z-disp\n";
  WriteText(path, header + "         7  1.0E+00  2.0E+00\n");
  EXPECT_EQ(ModelErrorOf([&] { ReadNodout(path, ModelUnits{}); }),
            path.string() + " line 4: the row is not a node id and 3 numbers.");
  WriteText(path, header + "         7  1.0E+00  2.0E+00  x.0E+00\n");
  EXPECT_EQ(ModelErrorOf([&] { ReadNodout(path, ModelUnits{}); }),
            path.string() + " line 4: the row is not a node id and 3 numbers.");
  WriteText(path,
            " n o d a l   p r i n t   o u t   f o r   t i m e  s t e p       1  ( at time 0.00000E+00 )\n\n"
            " nodal point  x-disp     y-wobble\n");
  EXPECT_EQ(ModelErrorOf([&] { ReadNodout(path, ModelUnits{}); }),
            path.string() + " line 3: the column 'y-wobble' is not a nodout column.");
  WriteText(path, "nothing here\n");
  EXPECT_EQ(ModelErrorOf([&] { ReadNodout(path, ModelUnits{}); }),
            path.string() + " line 1: the file has no nodout block (\"n o d a l   p r i n t\").");
  WriteText(
      path,
      header + "         7  1.0E+00  2.0E+00  3.0E+00\n\n" +
          " n o d a l   p r i n t   o u t   f o r   t i m e  s t e p       2  ( at time 0.00000E+00 )\n\n"
          " nodal point  x-disp     y-disp      z-disp\n         7  1.0E+00  2.0E+00  3.0E+00\n");
  EXPECT_EQ(ModelErrorOf([&] { ReadNodout(path, ModelUnits{}); }),
            path.string() + " line 6: the time 0 does not follow the previous one (0); times must increase.");
  EXPECT_EQ(ModelErrorOf([&] { ReadNodout(dir / "missing", ModelUnits{}); }),
            (dir / "missing").string() + ": cannot open the file (No such file or directory).");
}

// A model file is opened once, through one descriptor: its hash is of the bytes
// parsed, a file whose bytes change after it was opened is refused when read,
// and what is not a regular file (a folder, a FIFO no one writes to) is
// refused at once, never waited on.
TEST(ModelFile, OpenedOnceWithTheHashOfItsBytesAndOnlyFromARegularFile) {
  TempDir dir;
  const std::string text = "time_s,head_g\n0,1\n0.001,2\n";
  WriteText(dir / "model.csv", text);
  const formats::ModelFile file = ReadModelFile(dir / "model.csv");
  EXPECT_EQ(file.head, text);
  EXPECT_EQ(file.sha256, util::Sha256Hex(text));
  ASSERT_EQ(ReadModelCsv(file).size(), 1u);
  // Each reader reads the descriptor from its start: twice gives the same curve.
  EXPECT_EQ(ReadModelCsv(file).front().series.values, ReadModelCsv(dir / "model.csv").front().series.values);
  // The same file rewritten in place (its inode kept): the bytes are not those hashed.
  WriteText(dir / "model.csv", "time_s,head_g\n0,1\n0.001,3\n");
  EXPECT_EQ(
      ModelErrorOf([&] { ReadModelCsv(file); }),
      (dir / "model.csv").string() +
          ": changed while napkin read it (its bytes are no longer those it opened); rate it once it is "
          "written.");

  EXPECT_EQ(ModelErrorOf([&] { ReadModelFile(dir.path()); }),
            dir.path().string() + ": is a folder, not a regular file; napkin reads only regular files.");
  ASSERT_EQ(::mkfifo((dir / "pipe").c_str(), 0600), 0);
  EXPECT_EQ(ModelErrorOf([&] { ReadModelCsv(dir / "pipe"); }),
            (dir / "pipe").string() +
                ": is a FIFO (named pipe), not a regular file; napkin reads only regular files.");
}

TEST(ModelCsv, ReadsUnitsFromColumnSuffixes) {
  TempDir dir;
  const auto path = dir / "model.csv";
  WriteText(path,
            "# a model's head response\n"
            "time_ms,acc_x_g,omega_y_degps,alpha_z_radps2,quat_w,roll_deg,acc_y_g\n"
            "0,1,180,5,1,90,\n"
            "0.5,2,-180,6,0.5,45,\n");
  const std::vector<ModelCurve> curves = ReadModelCsv(path);
  ASSERT_EQ(curves.size(), 5u);  // acc_y_g is empty throughout: left out
  EXPECT_EQ(curves[0].name, "acc_x_g");
  EXPECT_EQ(curves[0].dimension, kAccelerationDimension);
  EXPECT_NEAR(curves[0].series.values(1), 2 * 9.80665, 1e-12);
  EXPECT_NEAR(curves[0].series.time_s(1), 0.5e-3, 1e-18);
  EXPECT_NEAR(curves[1].series.values(1), -std::numbers::pi, 1e-12);
  EXPECT_EQ(curves[1].dimension, kAngularVelocityDimension);
  EXPECT_EQ(curves[2].dimension, kAngularAccelerationDimension);
  EXPECT_EQ(curves[3].dimension, Dimension{});
  EXPECT_NEAR(curves[4].series.values(0), std::numbers::pi / 2, 1e-12);

  WriteText(path, "time_s,acc_x_g\n0,1\n0.001,oops\n");
  EXPECT_EQ(ModelErrorOf([&] { ReadModelCsv(path); }),
            path.string() + " line 3: column 'acc_x_g' holds 'oops', which is not a finite number.");
  WriteText(path, "time_s,acc_x_g\n0,1\n0.001\n");
  EXPECT_EQ(ModelErrorOf([&] { ReadModelCsv(path); }),
            path.string() + " line 3: the row has 1 fields, but the header has 2.");
  WriteText(path, "t,acc_x_g\n0,1\n");
  EXPECT_EQ(ModelErrorOf([&] { ReadModelCsv(path); }),
            path.string() + " line 1: the header has no time_s (or time_ms) column.");
  WriteText(path, "time_s,acc_x_g\n0,1\n0,2\n");
  EXPECT_EQ(ModelErrorOf([&] { ReadModelCsv(path); }),
            path.string() + " line 3: the time 0 does not follow the previous one (0); times must increase.");
  WriteText(path, "time_s,acc_x_g,acc_y_g\n0,1,1\n0.1,2,\n");
  EXPECT_EQ(ModelErrorOf([&] { ReadModelCsv(path); }),
            path.string() + " line 3: column 'acc_y_g' is empty, but other rows have a value there.");
}

TEST(LsDynaCurves, ReadsFreeAndFixedFormatAndRefusesOffsets) {
  TempDir dir;
  const auto path = dir / "model.k";
  WriteText(path,
            "*KEYWORD\n*DEFINE_CURVE_TITLE\nhead x\n$ lcid sidr sfa sfo\n7,0,1000.0,2.0\n0.0,1.0\n1.0,3.0\n"
            "*DEFINE_CURVE\n         8\n                 0.0                 5.0\n                 "
            "2.0                 6.0\n*END\n");
  const std::vector<ModelCurve> curves = ReadLsDynaCurves(path, ParseModelUnits("mm,ms,kg"));
  ASSERT_EQ(curves.size(), 2u);
  EXPECT_EQ(curves[0].name, "curve 7 head x");
  EXPECT_FALSE(curves[0].dimension);
  EXPECT_NEAR(curves[0].series.time_s(1), 1.0, 1e-15);  // 1 ms times SFA 1000
  EXPECT_EQ(curves[0].series.values(1), 6.0);           // SFO 2
  const ModelCurve si = ToSi(curves[1], kAccelerationDimension, ParseModelUnits("mm,ms,kg"));
  EXPECT_NEAR(si.series.values(1), 6000.0, 1e-9);
  EXPECT_NEAR(si.series.time_s(1), 2e-3, 1e-18);

  WriteText(path, "*DEFINE_CURVE\n7,0,1.0,1.0,0.5\n0.0,1.0\n1.0,3.0\n");
  EXPECT_EQ(
      ModelErrorOf([&] { ReadLsDynaCurves(path, ModelUnits{}); }),
      path.string() +
          " line 2: curve 7 has an offset (OFFA or OFFO), which napkin does not read; write it without.");
  WriteText(path, "*DEFINE_CURVE\n7\n0.0,1.0\n1.0,x\n");
  EXPECT_EQ(ModelErrorOf([&] { ReadLsDynaCurves(path, ModelUnits{}); }),
            path.string() + " line 4: curve 7's point '1.0,x' is not two numbers (abscissa, ordinate).");
  WriteText(path, "*KEYWORD\n*END\n");
  EXPECT_EQ(ModelErrorOf([&] { ReadLsDynaCurves(path, ModelUnits{}); }),
            path.string() + " line 2: the keyword file has no *DEFINE_CURVE.");
}

// A production-trim head impact of the padding series, processed as napkin
// does (CFC 1000 by default), optionally with the sensors 5 mm off their
// nominal places or CFC 180.
engine::Kinematics ProcessedImpact(bool displaced, std::optional<double> linear_cfc) {
  const engine::ArrayGeometry nominal = test_support::Ideal3222();
  const engine::ArrayGeometry truth = displaced ? synth::DisplaceSensors(nominal, 0.005, 7) : nominal;
  const synth::SyntheticTest test =
      synth::SynthHeadImpact(truth, synth::ScatteredImpact(synth::kPaddingVariants[0], 1));
  engine::ProcessingConfig config;
  if (linear_cfc) config.filter.linear_cfc = linear_cfc;
  return engine::ProcessTest(nominal, test.signals, test.initial, config).kinematics;
}

// The test's channel on the time axis of napkin's export (from 0).
engine::TimeSeries Channel(const engine::Kinematics& k, const engine::Series3& series, int column) {
  return {k.time_s.array() - k.time_s(0), series.col(column)};
}

TEST(LsDynaCurves, NapkinsOwnExportRatesOneAndWorseModelsBelow) {
  TempDir dir;
  const engine::Kinematics test = ProcessedImpact(false, std::nullopt);
  auto rate_export = [&](const engine::Kinematics& model, int curve, const engine::Series3& channel,
                         int column, Dimension dimension) {
    WriteLsDynaKeyword(model, dir / "model.k");
    const std::vector<ModelCurve> curves = ReadLsDynaCurves(dir / "model.k", ParseModelUnits("m,s,kg"));
    const ModelCurve read =
        ToSi(curves.at(static_cast<std::size_t>(curve)), dimension, ParseModelUnits("m,s,kg"));
    return engine::Iso18571RateCurves(Channel(test, channel, column), read.series);
  };
  // Curves 1-3: CG velocity X, Y, Z (m/s); 4-6: angular velocity X, Y, Z (rad/s).
  const engine::Iso18571Rating velocity = rate_export(test, 0, test.vel_fixed, 0, kVelocityDimension);
  const engine::Iso18571Rating omega = rate_export(test, 4, test.omega_fixed, 1, kAngularVelocityDimension);
  EXPECT_GE(velocity.overall, 0.9995);  // 1.000 to three decimals
  EXPECT_GE(omega.overall, 0.9995);
  EXPECT_EQ(velocity.grade, engine::Iso18571Grade::kExcellent);

  const engine::Kinematics displaced = ProcessedImpact(true, std::nullopt);
  const engine::Kinematics cfc180 = ProcessedImpact(false, engine::kCfc180);
  const engine::Iso18571Rating displaced_omega =
      rate_export(displaced, 4, test.omega_fixed, 1, kAngularVelocityDimension);
  const engine::Iso18571Rating cfc180_omega =
      rate_export(cfc180, 4, test.omega_fixed, 1, kAngularVelocityDimension);
  std::printf("omega_y: export %.4f, displaced array %.4f, CFC 180 %.4f\n", omega.overall,
              displaced_omega.overall, cfc180_omega.overall);
  EXPECT_LT(displaced_omega.overall, 0.9995);
  EXPECT_LT(cfc180_omega.overall, 0.9995);
  EXPECT_LT(displaced_omega.overall, omega.overall);
  EXPECT_LT(cfc180_omega.overall, omega.overall);
}

}  // namespace
}  // namespace napkin::formats
