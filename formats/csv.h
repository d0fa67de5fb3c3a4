#pragma once
// CSV signals (docs/formats.md "CSV input") and the derived-channel CSV
// (docs/formats.md "Derived channels", a contract other programs rely on).
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "engine/array_geometry.h"
#include "engine/kinematics.h"
#include "engine/signals.h"
#include "util/atomic_file.h"

namespace napkin::formats {

struct CsvSignals {
  engine::TestSignals signals;
  std::vector<std::string> warnings;  // one sentence each (ignored extra columns)
};

// Which CSV column feeds a slot (`--column SLOT=NAME`, a channel map's
// "column" entries; docs/formats.md "CSV input"): slot -> column name.
// "time_s" may be mapped too. A slot not listed is read from its own name.
using CsvColumnMap = std::vector<std::pair<std::string, std::string>>;

// Reads a signals CSV: '#' comment lines, a header `time_s` + columns, one
// row per sample. With `array`, the result has one column per sensor of the
// array in the array's order (missing slot columns are errors naming the
// slot, extra columns are ignored with a warning); without, every column
// but time_s in file order. `columns` renames the columns slots (and time_s)
// are read from. Throws InputError naming the file, the row (file line
// number) and the column at fault.
CsvSignals ReadSignalsCsv(const std::filesystem::path& path, const engine::ArrayGeometry* array = nullptr,
                          const CsvColumnMap& columns = {});

// The sampling of sample times `time_s` (at least two): strictly increasing,
// each step within 1e-6 (relative) of the mean step (docs/formats.md "CSV
// input"). Returns the first time and the mean step. Throws InputError
// starting with `source` and naming the sample at fault by `sample_name(k)`
// ("row 12": its file line; the previous one is "the previous `noun`'s").
// The CSV reader and app::SignalsFromSamples (napkin.transform) check time alike.
struct TimeBase {
  double t0_s = 0.0;
  double dt_s = 0.0;
};
TimeBase UniformTimeBase(std::span<const double> time_s, const std::string& source,
                         const std::function<std::string(std::size_t)>& sample_name, std::string_view noun);

// The other checks of a test's samples that the CSV reader and samples given
// in memory (app::SignalsFromSamples: napkin.transform's arrays) share, each
// refusal one sentence. A value that is no finite number, `where` naming its
// row and column ("in.csv: row 19, column \"cg_y\"", "in: sample 17, channel
// \"cg_y\"") and `written` the value as written: "<where>: \"nan\" is not a
// finite number."
[[noreturn]] void RefuseNonFiniteSample(const std::string& where, std::string_view written);
// Fewer than two samples (`unit`: what a sample is called, "data row",
// "sample"): "<source>: has 1 data row, at least two are needed."
void CheckSampleCount(std::size_t samples, const std::string& source, std::string_view unit);

// Parses `--column SLOT=NAME` values into a CsvColumnMap; throws UsageError
// for a value without '=' or with an empty side, or a slot given twice.
CsvColumnMap ParseCsvColumnOptions(const std::vector<std::string>& options);

// Writes raw signals (time_s + one column per slot), numbers in their
// shortest exact form so the file reads back to identical samples, after
// `comments` as '#' lines (each one line of text; docs/formats.md "CSV input").
void WriteSignalsCsv(const engine::TestSignals& signals, const std::filesystem::path& path,
                     std::span<const std::string> comments = {});

// The derived-channel columns, in contract order.
const std::vector<std::string>& DerivedCsvColumns();

// One derived channel in the unit of its CSV column (acceleration in g,
// angles in degrees, everything else SI). `values` is empty for a channel the
// test does not have: an acceleration-only test (engine::HasRotation false)
// has time_s and acc_body only, whose other cells the CSV leaves empty.
struct DerivedChannel {
  std::string name;
  Eigen::VectorXd values;
};

// Where one derived channel is in `kinematics`: its column in SI units
// (empty for a channel the test does not have, as DerivedChannel) and the
// factor from SI to the unit of its CSV column.
struct DerivedChannelSource {
  std::string_view name;
  std::span<const double> values_si;
  double to_csv_unit;
};

// The one list of derived channels, one per DerivedCsvColumns() entry in that
// order (docs/formats.md "Derived channels"); the spans point into
// `kinematics`. DerivedChannels copies and scales them; the Python module
// scales its own kinematics in place and hands the columns to numpy without
// a copy.
std::vector<DerivedChannelSource> DerivedChannelSources(const engine::Kinematics& kinematics);

// The derived channels of `kinematics` (DerivedChannelSources, scaled): what
// WriteDerivedCsv writes (rounded there to 12 digits) and
// Catalogue.channels() in Python returns.
std::vector<DerivedChannel> DerivedChannels(const engine::Kinematics& kinematics);

// Writes the derived channels: acc in g, angles in degrees, everything else
// SI; 12 significant digits.
void WriteDerivedCsv(const engine::Kinematics& kinematics, const std::filesystem::path& path);
// The same into an output already opened (several outputs committed together).
void WriteDerivedCsv(const engine::Kinematics& kinematics, util::AtomicFile& file);
// The same bytes as text (`napkin serve`'s channels route, docs/serve.md).
std::string DerivedCsvText(const engine::Kinematics& kinematics);

}  // namespace napkin::formats
