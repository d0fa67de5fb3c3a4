#pragma once
// CSV signals (docs/formats.md "CSV input") and the derived-channel CSV
// (docs/formats.md "Derived channels", a contract other programs rely on).
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "engine/array_geometry.h"
#include "engine/kinematics.h"
#include "engine/signals.h"

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

// Parses `--column SLOT=NAME` values into a CsvColumnMap; throws UsageError
// for a value without '=' or with an empty side, or a slot given twice.
CsvColumnMap ParseCsvColumnOptions(const std::vector<std::string>& options);

// Writes raw signals (time_s + one column per slot), numbers in their
// shortest exact form so the file reads back to identical samples.
void WriteSignalsCsv(const engine::TestSignals& signals, const std::filesystem::path& path);

// The derived-channel columns, in contract order.
const std::vector<std::string>& DerivedCsvColumns();

// Writes the derived channels: acc in g, angles in degrees, everything else
// SI; 12 significant digits.
void WriteDerivedCsv(const engine::Kinematics& kinematics, const std::filesystem::path& path);

}  // namespace napkin::formats
