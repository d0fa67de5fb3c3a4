// A model's curve chosen for a channel (app/correlation.h LoadModelCurve;
// docs/formats.md "Correlation ratings"): the curve rated is, bit for bit, the
// curve the file's reader reads, converted to SI by the units given; only the
// curves that may be rated are kept (issue 42, point 14), and the choice is the
// same as with every curve kept: the file's one curve (also when the columns
// before it are empty throughout), the one named like the channel, COLUMN by
// name or LCID, a node's resultant; two curves a name fits are ambiguous.
// The rating options and FILE:COLUMN parsed.
#include "app/correlation.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "common/error.h"
#include "formats/model_curves.h"
#include "tests/app/app_test_util.h"
#include "tests/support/test_support.h"
#include "util/sha256.h"
#include "util/text.h"

namespace napkin::app {
namespace {

void WriteModelText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

ChannelCurve ChannelNamed(const std::string& name, formats::Dimension dimension) {
  ChannelCurve curve;
  curve.name = name;
  curve.dimension = dimension;
  return curve;
}

// Three *DEFINE_CURVE, the second titled, with times and values that differ per curve.
std::string ThreeCurveKeyword() {
  std::string text = "*KEYWORD\n";
  for (int c = 0; c < 3; ++c) {
    text += c == 1 ? "*DEFINE_CURVE_TITLE\nhead omega x\n" : "*DEFINE_CURVE\n";
    text += std::to_string(3 + c) + ",0,1.0," + (c == 1 ? "2.0" : "1.0") + "\n";
    for (int k = 0; k < 50; ++k)
      text += util::FormatNumber(k * 0.5) + "," + util::FormatNumber((k % 9 - 4) * (c + 1) / 4.0) + "\n";
  }
  return text + "*END\n";
}

TEST(LoadModelCurve, TheCurveRatedIsTheReadersCurveInTheUnitsGiven) {
  test_support::TempDir dir;
  const std::string path = (dir / "head.k").string();
  const std::string text = ThreeCurveKeyword();
  WriteModelText(path, text);
  const formats::ModelUnits units = formats::ParseModelUnits("mm,ms,kg");
  const std::vector<formats::ModelCurve> every = formats::ReadLsDynaCurves(path, units);
  const ChannelCurve omega = ChannelNamed("omega_fixed_x_radps", formats::kAngularVelocityDimension);
  for (const std::string column : {"4", "curve 4 head omega x"}) {
    const ModelReference chosen = LoadModelCurve(path + ":" + column, omega, std::string("MM, ms, kg"));
    EXPECT_EQ(chosen.file_name, "head.k");
    EXPECT_EQ(chosen.sha256, util::Sha256Hex(text));
    EXPECT_EQ(chosen.column, "curve 4 head omega x");
    EXPECT_EQ(chosen.units, "mm,ms,kg");
    // 1 rad/ms = 1000 rad/s; times in ms; SFO 2: exactly as the reader with every curve and ToSi.
    const formats::ModelCurve expected = formats::ToSi(every[1], formats::kAngularVelocityDimension, units);
    EXPECT_EQ(chosen.series.time_s, expected.series.time_s);
    EXPECT_EQ(chosen.series.values, expected.series.values);
    EXPECT_EQ(chosen.series.values(1), -3 * 2 / 4.0 * 2.0 * 1000.0);
    EXPECT_EQ(chosen.series.time_s(2), 1.0 * 1e-3);
  }
  // Without COLUMN, three curves and none named like the channel: refused listing them.
  EXPECT_EQ(
      test_support::ErrorText<InputError>([&] { LoadModelCurve(path, omega, std::string("mm,ms,kg")); }),
      "model file '" + path +
          "' holds 3 curves and none named omega_fixed_x_radps; name one as FILE:COLUMN, one of 'curve 3', "
          "'curve 4 head omega x', 'curve 5'.");
  EXPECT_EQ(test_support::ErrorText<InputError>(
                [&] { LoadModelCurve(path + ":6", omega, std::string("mm,ms,kg")); }),
            "model file '" + path +
                "' has no curve '6'; its curves are 'curve 3', 'curve 4 head omega x', 'curve 5'.");
}

TEST(LoadModelCurve, WithoutAColumnTheFilesOneCurveOrTheOneNamedLikeTheChannel) {
  test_support::TempDir dir;
  const std::string path = (dir / "model.csv").string();
  const ChannelCurve resultant = ChannelNamed("acc_resultant_g", formats::kAccelerationDimension);
  // The file's one curve, after a column empty throughout (read again for it alone: the reader
  // keeps the first column it is offered, which is no curve).
  WriteModelText(path, "time_s,acc_body_x_g,head_g\n0,,1\n0.001,,3\n0.002,,2\n");
  const ModelReference one = LoadModelCurve(path, resultant, std::nullopt);
  EXPECT_EQ(one.column, "head_g");
  EXPECT_FALSE(one.units);
  EXPECT_EQ(one.series.values, formats::ReadModelCsv(formats::ReadModelFile(path)).front().series.values);
  EXPECT_EQ(one.series.values(1), 3 * 9.80665);
  // The column named like the channel among others, wherever it is.
  WriteModelText(path,
                 "time_s,acc_body_x_g,acc_resultant_g,acc_body_z_g\n0,1,2,3\n0.001,4,6,5\n0.002,7,8,9\n");
  const ModelReference named = LoadModelCurve(path, resultant, std::nullopt);
  EXPECT_EQ(named.column, "acc_resultant_g");
  EXPECT_EQ(named.series.values, (Eigen::VectorXd(3) << 2 * 9.80665, 6 * 9.80665, 8 * 9.80665).finished());
  // Two columns named like the channel: ambiguous, not the first or the last taken silently.
  WriteModelText(path, "time_s,acc_resultant_g,acc_resultant_g\n0,1,2\n0.001,4,6\n");
  EXPECT_EQ(test_support::ErrorText<InputError>([&] { LoadModelCurve(path, resultant, std::nullopt); }),
            "model file '" + path +
                "' has 2 curves named 'acc_resultant_g' ('acc_resultant_g', 'acc_resultant_g'), so which one "
                "to rate "
                "is ambiguous; give each column its own name.");
  // --model-units for a CSV: its header gives its units.
  EXPECT_THROW(LoadModelCurve(path + ":acc_resultant_g", resultant, std::string("m,s,kg")), UsageError);
}

TEST(RatingOptions, TimesAndEditionFromTheirText) {
  const RatingOptions open = ParseRatingOptions("acc_resultant_g", "", "", "2024");
  EXPECT_FALSE(open.start_s);
  EXPECT_FALSE(open.end_s);
  EXPECT_EQ(open.edition, engine::Iso18571Edition::k2024);
  const RatingOptions closed = ParseRatingOptions("omega_body_y_radps", "0.01", "0.05", "2014");
  EXPECT_EQ(closed.start_s, 0.01);
  EXPECT_EQ(closed.end_s, 0.05);
  EXPECT_EQ(closed.edition, engine::Iso18571Edition::k2014);
  EXPECT_THROW(ParseRatingOptions("acc_resultant_g", "0.05", "0.01", "2024"), UsageError);
  EXPECT_THROW(ParseRatingOptions("acc_resultant_g", "soon", "", "2024"), UsageError);
  EXPECT_THROW(ParseRatingOptions("acc_resultant_g", "", "", "2020"), UsageError);
  EXPECT_THROW(ParseRatingOptions("head_g", "", "", "2024"), UsageError);
}

TEST(ModelSpec, TheLongestPrefixThatIsAFileAndTheColumnAfterIt) {
  test_support::TempDir dir;
  const std::string path = (dir / "a:b.csv").string();
  WriteModelText(path, "time_s,x_g\n0,1\n1,2\n");
  EXPECT_EQ(ParseModelSpec(path).path, path);
  EXPECT_EQ(ParseModelSpec(path).column, "");
  EXPECT_EQ(ParseModelSpec(path + ":x_g").path, path);
  EXPECT_EQ(ParseModelSpec(path + ":x_g").column, "x_g");
  EXPECT_EQ(ParseModelSpec(path + ":node 1:2").column, "node 1:2");
  EXPECT_EQ(ParseModelSpec((dir / "missing.csv:x").string()).path, (dir / "missing.csv:x").string());
}

// FILE:NODE for a resultant channel is the node's resultant of its x, y and z columns (frame-free),
// as computed by hand from the components (issue 42, point 16: only `node 1234 x-accl` worked).
TEST(LoadModelCurve, ANodeAloneGivesItsResultantForAResultantChannel) {
  // A nodout in mm, ms, kg (the layout of tests/fixtures/iso18571/make_nodout.py) whose node 1234
  // accelerates along all three axes, differently in time.
  test_support::TempDir dir;
  const std::string nodout = (dir.path() / "nodout").string();
  {
    std::string text;
    char field[64];
    for (int step = 1; step <= 21; ++step) {
      const double t = 0.5 * (step - 1);
      std::snprintf(field, sizeof field, "%8d", step);
      text += std::string(" n o d a l   p r i n t   o u t   f o r   t i m e  s t e p") + field;
      std::snprintf(field, sizeof field, "%.5E", t);
      text += std::string("                              ( at time ") + field + " )\n\n";
      text +=
          " nodal point  x-disp     y-disp      z-disp      x-vel       y-vel       z-vel       x-accl      "
          "y-accl  "
          "    z-accl      x-coor      y-coor      z-coor\n";
      std::snprintf(field, sizeof field, "%10d", 1234);
      text += field;
      for (const double value :
           {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, t, 2.0 - 0.1 * t, -0.05 * t * t, 100.0, 0.0, 0.0}) {
        std::snprintf(field, sizeof field, "%12.4E", value);
        text += field;
      }
      text += "\n\n";
    }
    WriteModelText(nodout, text);
  }
  const auto channel = [](const std::string& name) {
    ChannelCurve curve;
    curve.name = name;
    curve.dimension = formats::kAccelerationDimension;
    return curve;
  };
  const ModelReference resultant =
      LoadModelCurve(nodout + ":1234", channel("acc_resultant_g"), std::string("mm,ms,kg"));
  EXPECT_EQ(resultant.column, "node 1234 resultant accl");
  EXPECT_EQ(LoadModelCurve(nodout + ":node 1234", channel("acc_resultant_g"), std::string("mm,ms,kg")).column,
            "node 1234 resultant accl");
  Eigen::VectorXd by_hand;
  for (const char* axis : {"x", "y", "z"}) {
    const ModelReference component =
        LoadModelCurve(nodout + ":1234 " + axis + "-accl", channel(std::string("acc_body_") + axis + "_g"),
                       std::string("mm,ms,kg"));
    if (by_hand.size() == 0) by_hand = Eigen::VectorXd::Zero(component.series.values.size());
    by_hand += component.series.values.array().square().matrix();
    EXPECT_EQ(component.series.time_s, resultant.series.time_s);
  }
  by_hand = by_hand.array().sqrt();
  ASSERT_EQ(by_hand.size(), resultant.series.values.size());
  for (Eigen::Index i = 0; i < by_hand.size(); ++i)
    EXPECT_DOUBLE_EQ(resultant.series.values(i), by_hand(i)) << i;
  EXPECT_GT(resultant.series.values.maxCoeff(), 0.0);
  // A component channel still needs its column.
  EXPECT_THROW(LoadModelCurve(nodout + ":1234", channel("acc_body_x_g"), std::string("mm,ms,kg")),
               InputError);
}

}  // namespace
}  // namespace napkin::app
