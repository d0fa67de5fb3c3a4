#pragma once
// A finite-element model's head response as the engineer has it, read for
// the ISO/TS 18571 rating (engine/iso18571.h; docs/formats.md "Model
// curves"): a CSV (time_s plus columns whose names end in their unit), the
// LS-DYNA keyword *DEFINE_CURVE (napkin's own export reads back), and the
// LS-DYNA ASCII nodout (nodal displacements, velocities, accelerations and
// rotations). LS-DYNA files carry no units: the reader takes the model's
// unit system ("mm,ms,kg", "m,s,kg", ...; `--model-units`).
// Every error is one sentence naming the file and its line.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/overlay.h"

namespace napkin::formats {

// A model's consistent unit system: SI per unit of length, time and mass.
struct ModelUnits {
  double metres = 1.0;   // per length unit
  double seconds = 1.0;  // per time unit
  double kilograms = 1.0;
};

// "LENGTH,TIME,MASS": length m, cm, mm, in or ft; time s, ms or us; mass kg,
// g, t (tonne) or lbf-s2/in. Throws UsageError naming `option` (e.g.
// "--model-units") for any other spelling.
ModelUnits ParseModelUnits(std::string_view spec, std::string_view option = "--model-units");

// A model file as read, once, through one descriptor: its bytes and their
// SHA-256. The readers below parse these bytes, so a rating stored under a
// file's hash is the rating of exactly those bytes, whatever happens to the
// path meanwhile (docs/formats.md "Model curves"). The path-taking readers
// read the file this way first.
// The largest model file read (64 MiB: over a million points of a CSV, far more than any head
// impact model's output): with its parsed curves in memory, a few hundred MB at most.
inline constexpr std::uintmax_t kMaxModelFileBytes = std::uintmax_t{64} << 20;

struct ModelFile {
  std::filesystem::path path;  // as given, for messages
  std::string bytes;
  std::string sha256;  // hex, of `bytes`
};

// Opens `path` once (O_RDONLY, O_NOCTTY, O_NONBLOCK: a FIFO or device never
// blocks), refuses anything fstat does not call a regular file, reads it
// whole. Throws InputError naming the file.
ModelFile ReadModelFile(const std::filesystem::path& path);

// Powers of length, time and mass of a quantity (acceleration: 1, -2, 0).
struct Dimension {
  int length = 0;
  int time = 0;
  int mass = 0;
  bool operator==(const Dimension&) const = default;
};
inline constexpr Dimension kLengthDimension{1, 0, 0};
inline constexpr Dimension kVelocityDimension{1, -1, 0};
inline constexpr Dimension kAccelerationDimension{1, -2, 0};
inline constexpr Dimension kAngleDimension{0, 0, 0};
inline constexpr Dimension kAngularVelocityDimension{0, -1, 0};
inline constexpr Dimension kAngularAccelerationDimension{0, -2, 0};

// SI per unit of a quantity of `dimension` in `units` (1 mm/ms^2 = 1000 m/s^2).
double SiPerUnit(const ModelUnits& units, Dimension dimension);

struct ModelCurve {
  // CSV: the column's name; keyword: "curve LCID" (the title after it when
  // given, "curve 7 head x"); nodout: "node NID x-accl" (the nodout column).
  std::string name;
  // Known for CSV columns and nodout columns, whose values are then SI;
  // nullopt for a *DEFINE_CURVE (the keyword does not say), whose values
  // are as written times SFO (ToSi converts them once the quantity is known).
  std::optional<Dimension> dimension;
  engine::TimeSeries series;  // time in s
};

// Values of a curve without a dimension (a *DEFINE_CURVE), taken as
// `dimension` in `units`, converted to SI.
ModelCurve ToSi(ModelCurve curve, Dimension dimension, const ModelUnits& units);

// Model CSV: '#' comment lines, a header with `time_s` (or `time_ms`) and
// columns whose names end in a unit suffix: _g, _mps2, _radps, _degps,
// _radps2, _mps, _m, _mm, _rad, _deg (napkin's derived-channel CSV is one:
// `export --format csv` reads back); other columns are kept as numbers
// without a unit (dimension 0, factor 1). A column empty in every row is
// left out; a single empty, non-numeric or non-finite cell is an error.
// Whether a model CSV column's name ends in a unit the reader knows (_g, _mps2, _radps, _deg, ...);
// a column without one is read as a number without dimension, which is no channel's quantity.
bool ModelCsvColumnHasUnit(std::string_view name);
// The unit suffixes of model CSV columns, for sentences: "_mps2, _radps2, ...".
std::string ModelCsvUnitSuffixes();

std::vector<ModelCurve> ReadModelCsv(const std::filesystem::path& path);
std::vector<ModelCurve> ReadModelCsv(const ModelFile& file);

// Every *DEFINE_CURVE (and *DEFINE_CURVE_TITLE) of a keyword file, fixed
// columns (10-character card 1, 20-character points) or comma-separated:
// abscissae are times in the unit system's time unit, scaled by SFA;
// ordinates scaled by SFO. Offsets (OFFA, OFFO) other than 0 are refused.
std::vector<ModelCurve> ReadLsDynaCurves(const std::filesystem::path& path, const ModelUnits& units);
std::vector<ModelCurve> ReadLsDynaCurves(const ModelFile& file, const ModelUnits& units);

// An LS-DYNA ASCII nodout: per output time a block " n o d a l   p r i n t
// o u t   f o r   t i m e  s t e p N ( at time T )", a header of column
// names (x-disp ... z-accl, x-coor ...; or x-rot ... z-rot acc) and a row per
// node (node id, then the values; Fortran E fields may touch). One curve per
// node and column, in SI by `units`; every block must list the same nodes.
// `node`: only that node's curves (an error when the file has none).
std::vector<ModelCurve> ReadNodout(const std::filesystem::path& path, const ModelUnits& units,
                                   std::optional<long> node = std::nullopt);
std::vector<ModelCurve> ReadNodout(const ModelFile& file, const ModelUnits& units,
                                   std::optional<long> node = std::nullopt);

}  // namespace napkin::formats
