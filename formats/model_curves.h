#pragma once
// A finite-element model's head response as the engineer has it, read for
// the ISO/TS 18571 rating (engine/iso18571.h; docs/formats.md "Model
// curves"): a CSV (time_s plus columns whose names end in their unit), the
// LS-DYNA keyword *DEFINE_CURVE (napkin's own export reads back), and the
// LS-DYNA ASCII nodout (nodal displacements, velocities, accelerations and
// rotations). LS-DYNA files carry no units: the reader takes the model's
// unit system ("mm,ms,kg", "m,s,kg", ...; `--model-units`).
// Every error is one sentence naming the file and its line.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/overlay.h"
#include "util/unique_fd.h"

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

// A model file opened once: its descriptor, the first bytes that tell its
// form, and the SHA-256 of its bytes. The readers below read it through that
// descriptor in a stream, hash what they parse and refuse a file whose bytes
// changed since it was opened, so a rating stored under a file's hash is the
// rating of exactly those bytes, whatever happens to the path meanwhile
// (docs/formats.md "Model curves"). The path-taking readers open it first.
// The largest model file read (1 GiB, as any test data file,
// kMaxDataFileBytes) and the most points of one curve (2^24, 256 MiB as time
// and value doubles): a reader holds the curves it keeps and one line, never
// the file, so these two bound the memory a rating takes (issue 42, point 14).
// A kept curve's numbers are read into the vectors it keeps, allocated once
// for the most points the file's bytes can hold and touched only where
// written: about its doubles once (bench/run_model_memory.sh: 1.08x for a
// 10^7-point *DEFINE_CURVE).
inline constexpr std::uintmax_t kMaxModelFileBytes = std::uintmax_t{1} << 30;
inline constexpr std::size_t kMaxModelCurvePoints = std::size_t{1} << 24;
// The longest line read (a model CSV's header of many columns is a few KiB).
inline constexpr std::size_t kMaxModelLineBytes = std::size_t{1} << 20;
// How much of the file ModelFile::head holds.
inline constexpr std::size_t kModelHeadBytes = std::size_t{64} << 10;

struct ModelFile {
  std::filesystem::path path;  // as given, for messages
  util::UniqueFd fd;           // read with pread, from offset 0 by each reader
  std::string head;            // the first kModelHeadBytes bytes (or all of a shorter file)
  std::string sha256;          // hex, of the bytes when opened
  std::uintmax_t bytes = 0;    // its size when opened
};

// Opens `path` once (O_RDONLY, O_NOCTTY, O_NONBLOCK: a FIFO or device never
// blocks), refuses anything fstat does not call a regular file and a file
// larger than kMaxModelFileBytes, and reads it through once for its hash.
// Throws InputError naming the file.
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

// Which of a file's curves a reader keeps: asked once per curve by its name
// (ModelCurve::name), in the order the file gives them, before the curve's
// points are read (a model CSV asks for every column of its header, also one
// that turns out empty throughout, which is no curve). A curve not kept is
// read and checked all the same, only not stored: reading a file takes the
// memory of the curves kept, not of the file.
using KeepCurve = std::function<bool(const std::string& name)>;

// A file's curves as a reader leaves them.
struct ModelCurves {
  std::vector<std::string> names;  // every curve of the file, in the order the readers return them
  std::vector<ModelCurve> kept;    // those `keep` asked for, in that order
};

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

// The readers without `keep` keep every curve.
std::vector<ModelCurve> ReadModelCsv(const std::filesystem::path& path);
std::vector<ModelCurve> ReadModelCsv(const ModelFile& file);
ModelCurves ReadModelCsv(const ModelFile& file, const KeepCurve& keep);

// Every *DEFINE_CURVE (and *DEFINE_CURVE_TITLE) of a keyword file, fixed
// columns (10-character card 1, 20-character points) or comma-separated:
// abscissae are times in the unit system's time unit, scaled by SFA;
// ordinates scaled by SFO. Offsets (OFFA, OFFO) other than 0 are refused.
std::vector<ModelCurve> ReadLsDynaCurves(const std::filesystem::path& path, const ModelUnits& units);
std::vector<ModelCurve> ReadLsDynaCurves(const ModelFile& file, const ModelUnits& units);
ModelCurves ReadLsDynaCurves(const ModelFile& file, const ModelUnits& units, const KeepCurve& keep);

// An LS-DYNA ASCII nodout: per output time a block " n o d a l   p r i n t
// o u t   f o r   t i m e  s t e p N ( at time T )", a header of column
// names (x-disp ... z-accl, x-coor ...; or x-rot ... z-rot acc) and a row per
// node (node id, then the values; Fortran E fields may touch). One curve per
// node and column, in SI by `units`; every block of a kind (translational,
// rotational) must have the columns and list the nodes of its first block,
// each node once.
// `node`: only that node's curves (an error when the file has none).
std::vector<ModelCurve> ReadNodout(const std::filesystem::path& path, const ModelUnits& units,
                                   std::optional<long> node = std::nullopt);
std::vector<ModelCurve> ReadNodout(const ModelFile& file, const ModelUnits& units,
                                   std::optional<long> node = std::nullopt);
ModelCurves ReadNodout(const ModelFile& file, const ModelUnits& units, const KeepCurve& keep);

}  // namespace napkin::formats
