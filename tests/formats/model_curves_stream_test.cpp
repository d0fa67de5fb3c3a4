// The model-curve readers read a file as a stream (formats/model_curves.h;
// issue 42, point 14: a 10^7-point model took 1.26 GB): generated keyword files
// and model CSVs with comments, blank lines, CRLF line ends, a line end split
// across the readers' 64 KiB chunks, several curves and more than one chunk
// read back to exactly the numbers written (the doubles written, scaled as
// docs/formats.md "Model curves" says); a curve kept alone is bit for bit the
// curve kept with all others, and the names are every curve's whatever is
// kept; nodout blocks that would make two curves of one name are refused.
// Memory itself is measured by bench/run_model_memory.sh, not here.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <string>
#include <vector>

#include "common/error.h"
#include "engine/units.h"
#include "formats/model_curves.h"
#include "tests/support/test_support.h"
#include "util/text.h"

namespace napkin::formats {
namespace {

using test_support::TempDir;

const std::filesystem::path kStreamNodout =
    std::filesystem::path(NAPKIN_FIXTURES_DIR) / "iso18571" / "nodout_mm_ms";

void WriteModelBytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

template <typename F>
std::string StreamErrorOf(F&& f) {
  try {
    f();
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

// `text` right-aligned in a fixed column of `width` (it must fit).
std::string FixedColumn(const std::string& text, std::size_t width) {
  EXPECT_LE(text.size(), width) << text;
  return std::string(width - std::min(width, text.size()), ' ') + text;
}

// A "$" or "#" comment line that ends the first 64 KiB chunk inside its line end: the '\r' of a
// CRLF the chunk's last byte, the '\n' the next chunk's first (with LF: the '\n' the last byte).
std::string ChunkSplittingComment(std::size_t written, char mark, const std::string& eol) {
  const std::size_t chunk = std::size_t{1} << 16;
  const std::size_t length = chunk - 1 - written;  // the comment's characters before its line end
  return mark + std::string(length - 1, 'x') + eol;
}

// The numbers of the generated curves: times k / 1024 and ordinates of eighths, all exact in
// binary and in their shortest decimal text.
double TimeOf(int k) { return k / 1024.0; }
double OrdinateOf(int k, int curve) { return ((k * (37 + 11 * curve)) % 1000 - 500) / 8.0; }

struct WrittenCurve {
  int lcid;
  std::string title;  // *DEFINE_CURVE_TITLE when not empty
  double sfa, sfo;
  int points;
  bool fixed_columns;  // else comma-separated
};

std::string KeywordFile(const std::vector<WrittenCurve>& curves, const std::string& eol) {
  std::string text = "*KEYWORD" + eol;
  text += ChunkSplittingComment(text.size(), '$', eol);
  for (std::size_t c = 0; c < curves.size(); ++c) {
    const WrittenCurve& curve = curves[c];
    text += "$ curve " + std::to_string(curve.lcid) + eol;
    text += curve.title.empty() ? "*DEFINE_CURVE" + eol : "*DEFINE_CURVE_TITLE" + eol + curve.title + eol;
    text += "$     lcid      sidr       sfa       sfo" + eol;
    const std::vector<std::string> card = {std::to_string(curve.lcid), "0", util::FormatNumber(curve.sfa),
                                           util::FormatNumber(curve.sfo)};
    if (curve.fixed_columns) {
      for (const std::string& field : card) text += FixedColumn(field, 10);
      text += eol;
    } else {
      text += card[0] + "," + card[1] + "," + card[2] + "," + card[3] + eol;
    }
    for (int k = 0; k < curve.points; ++k) {
      if (k == curve.points / 2) text += "$ half way" + eol;
      const std::string a = util::FormatNumber(TimeOf(k));
      const std::string o = util::FormatNumber(OrdinateOf(k, static_cast<int>(c)));
      text += (curve.fixed_columns ? FixedColumn(a, 20) + FixedColumn(o, 20) : a + "," + o) + eol;
    }
    text += eol;  // a blank line ends the points
  }
  return text + "*END" + eol;
}

TEST(ModelCurveStream, KeywordCurvesReadBackAsWrittenWhateverTheLayout) {
  TempDir dir;
  const ModelUnits units = ParseModelUnits("mm,ms,kg");
  const std::vector<WrittenCurve> written = {
      {7, "", 1.0, 1.0, 40, true}, {8, "head x", 2.0, 0.5, 3000, false}, {9, "", 1000.0, 3.0, 2500, true}};
  for (const std::string eol : {"\n", "\r\n"}) {
    const std::string text = KeywordFile(written, eol);
    ASSERT_GT(text.size(), std::size_t{3} << 16);  // more than three chunks
    ASSERT_EQ(text.substr((std::size_t{1} << 16) - 1, eol.size()), eol);
    WriteModelBytes(dir / "model.k", text);
    const ModelFile file = ReadModelFile(dir / "model.k");
    const std::vector<ModelCurve> curves = ReadLsDynaCurves(file, units);
    ASSERT_EQ(curves.size(), written.size());
    EXPECT_EQ(curves[0].name, "curve 7");
    EXPECT_EQ(curves[1].name, "curve 8 head x");
    for (std::size_t c = 0; c < written.size(); ++c) {
      const engine::TimeSeries& series = curves[c].series;
      EXPECT_FALSE(curves[c].dimension);
      ASSERT_EQ(series.time_s.size(), written[c].points) << c;
      ASSERT_EQ(series.values.size(), written[c].points) << c;
      for (int k = 0; k < written[c].points; ++k) {
        // Abscissae times SFA in the unit system's time unit, ordinates times SFO: exactly.
        ASSERT_EQ(series.time_s(k), TimeOf(k) * written[c].sfa * units.seconds) << c << " " << k;
        ASSERT_EQ(series.values(k), OrdinateOf(k, static_cast<int>(c)) * written[c].sfo) << c << " " << k;
      }
    }
    // The second curve alone: the same doubles, and every curve's name.
    const ModelCurves alone =
        ReadLsDynaCurves(file, units, [](const std::string& name) { return name == "curve 8 head x"; });
    EXPECT_EQ(alone.names, (std::vector<std::string>{"curve 7", "curve 8 head x", "curve 9"}));
    ASSERT_EQ(alone.kept.size(), 1u);
    EXPECT_EQ(alone.kept[0].name, "curve 8 head x");
    EXPECT_EQ(alone.kept[0].series.time_s, curves[1].series.time_s);
    EXPECT_EQ(alone.kept[0].series.values, curves[1].series.values);
    const ModelCurves none = ReadLsDynaCurves(file, units, [](const std::string&) { return false; });
    EXPECT_EQ(none.names, alone.names);
    EXPECT_TRUE(none.kept.empty());
  }
}

// A model CSV: '#' comments and blank lines between rows, a column empty throughout (no curve),
// CRLF, no line end after the last row.
std::string ModelCsvFile(int rows, const std::string& eol) {
  std::string text = "# a model's head response" + eol + eol;
  text += ChunkSplittingComment(text.size(), '#', eol);
  text += "time_ms, acc_x_g ,empty_g,roll_deg,plain" + eol;
  for (int k = 0; k < rows; ++k) {
    if (k % 1000 == 500) text += eol + "# a comment among the rows" + eol;
    text += util::FormatNumber(TimeOf(k)) + "," + util::FormatNumber(OrdinateOf(k, 0)) + ", ," +
            util::FormatNumber(OrdinateOf(k, 1)) + "," + util::FormatNumber(OrdinateOf(k, 2));
    if (k + 1 < rows) text += eol;
  }
  return text;
}

TEST(ModelCurveStream, ModelCsvColumnsReadBackAsWrittenWhateverTheLayout) {
  TempDir dir;
  const int rows = 6000;
  for (const std::string eol : {"\n", "\r\n"}) {
    const std::string text = ModelCsvFile(rows, eol);
    ASSERT_GT(text.size(), std::size_t{2} << 16);
    ASSERT_EQ(text.substr((std::size_t{1} << 16) - 1, eol.size()), eol);
    WriteModelBytes(dir / "model.csv", text);
    const ModelFile file = ReadModelFile(dir / "model.csv");
    const std::vector<ModelCurve> curves = ReadModelCsv(file);
    ASSERT_EQ(curves.size(), 3u);  // empty_g is empty throughout: no curve
    EXPECT_EQ(curves[0].name, "acc_x_g");
    EXPECT_EQ(curves[1].name, "roll_deg");
    EXPECT_EQ(curves[2].name, "plain");
    EXPECT_EQ(curves[0].dimension, kAccelerationDimension);
    EXPECT_EQ(curves[1].dimension, kAngleDimension);
    EXPECT_EQ(curves[2].dimension, Dimension{});
    const double per_unit[] = {engine::kStandardGravity, 1.0 / engine::kDegPerRad, 1.0};
    for (std::size_t c = 0; c < curves.size(); ++c) {
      ASSERT_EQ(curves[c].series.time_s.size(), rows);
      ASSERT_EQ(curves[c].series.values.size(), rows);
      for (int k = 0; k < rows; ++k) {
        ASSERT_EQ(curves[c].series.time_s(k), TimeOf(k) * 1e-3) << k;
        ASSERT_EQ(curves[c].series.values(k), OrdinateOf(k, static_cast<int>(c)) * per_unit[c])
            << c << " " << k;
      }
    }
    std::vector<std::string> asked;
    const ModelCurves alone = ReadModelCsv(file, [&](const std::string& name) {
      asked.push_back(name);
      return name == "roll_deg";
    });
    // Every column of the header is asked about, the empty one too; only curves are named.
    EXPECT_EQ(asked, (std::vector<std::string>{"acc_x_g", "empty_g", "roll_deg", "plain"}));
    EXPECT_EQ(alone.names, (std::vector<std::string>{"acc_x_g", "roll_deg", "plain"}));
    ASSERT_EQ(alone.kept.size(), 1u);
    EXPECT_EQ(alone.kept[0].series.time_s, curves[1].series.time_s);
    EXPECT_EQ(alone.kept[0].series.values, curves[1].series.values);
  }
}

TEST(ModelCurveStream, NodoutCurvesKeptAloneAreThoseReadWithAll) {
  const ModelUnits units = ParseModelUnits("mm,ms,kg");
  const ModelFile file = ReadModelFile(kStreamNodout);
  const std::vector<ModelCurve> all = ReadNodout(file, units);
  const std::vector<std::string> wanted = {"node 1234 z-rot-acc", "node 7 x-accl"};
  const ModelCurves some = ReadNodout(file, units, [&](const std::string& name) {
    return std::find(wanted.begin(), wanted.end(), name) != wanted.end();
  });
  ASSERT_EQ(some.names.size(), all.size());
  for (std::size_t c = 0; c < all.size(); ++c) EXPECT_EQ(some.names[c], all[c].name);
  ASSERT_EQ(some.kept.size(), 2u);
  for (const ModelCurve& kept : some.kept) {
    const auto same =
        std::find_if(all.begin(), all.end(), [&](const ModelCurve& c) { return c.name == kept.name; });
    ASSERT_NE(same, all.end());
    EXPECT_EQ(kept.dimension, same->dimension);
    EXPECT_EQ(kept.series.time_s, same->series.time_s);
    EXPECT_EQ(kept.series.values, same->series.values);
  }
  // In the names' order: by node id, then column.
  EXPECT_EQ(some.kept[0].name, "node 7 x-accl");
  EXPECT_EQ(some.kept[1].name, "node 1234 z-rot-acc");
}

// Blocks whose curves would not be one curve per node and column: a later block of a kind with
// other columns (its curves were as long as the columns' blocks, read past their end), a node twice
// in a block, a column twice, a rotational column among translational ones.
TEST(ModelCurveStream, NodoutBlocksThatWouldMakeTwoCurvesOfOneNameAreRefused) {
  TempDir dir;
  const auto path = dir / "nodout";
  const auto block = [](int step, const std::string& columns, const std::string& rows) {
    return " n o d a l   p r i n t   o u t   f o r   t i m e  s t e p       " + std::to_string(step) +
           "  ( at time " + std::to_string(step) + ".0E+00 )\n\n nodal point  " + columns + "\n" + rows +
           "\n";
  };
  const std::string row = "         7  1.0E+00  2.0E+00  3.0E+00\n";
  WriteModelBytes(path, block(1, "x-disp y-disp z-disp", row) + block(2, "x-vel y-vel z-vel", row));
  EXPECT_EQ(StreamErrorOf([&] { ReadNodout(path, ModelUnits{}); }),
            path.string() + " line 8: the columns are not those of the first block of their kind (line 1).");
  WriteModelBytes(path, block(1, "x-disp y-disp z-disp", row + row));
  EXPECT_EQ(StreamErrorOf([&] { ReadNodout(path, ModelUnits{}); }),
            path.string() + " line 5: the block lists node 7 twice.");
  WriteModelBytes(path, block(1, "x-disp y-disp x-disp", row));
  EXPECT_EQ(StreamErrorOf([&] { ReadNodout(path, ModelUnits{}); }),
            path.string() + " line 3: the column 'x-disp' is named twice.");
  WriteModelBytes(path, block(1, "x-disp y-disp x-rot", row));
  EXPECT_EQ(StreamErrorOf([&] { ReadNodout(path, ModelUnits{}); }),
            path.string() +
                " line 3: the block mixes rotational and translational columns ('x-disp' and 'x-rot').");
  // The same blocks with the same columns and nodes read.
  WriteModelBytes(path, block(1, "x-disp y-disp z-disp", row) + block(2, "x-disp y-disp z-disp", row));
  EXPECT_EQ(ReadNodout(path, ModelUnits{}).size(), 3u);
}

// A line longer than kMaxModelLineBytes is refused naming its line, not gathered whole.
TEST(ModelCurveStream, ALineBeyondTheLongestIsRefused) {
  TempDir dir;
  WriteModelBytes(dir / "model.csv",
                  "# comment\ntime_s," + std::string(kMaxModelLineBytes, 'a') + "_g\n0,1\n");
  EXPECT_EQ(StreamErrorOf([&] { ReadModelCsv(dir / "model.csv"); }),
            (dir / "model.csv").string() +
                " line 2: the line is longer than the 1 MiB napkin reads as one line of a model file.");
}

}  // namespace
}  // namespace napkin::formats
