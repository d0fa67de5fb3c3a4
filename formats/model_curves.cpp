#include "formats/model_curves.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <tuple>
#include <utility>

#include "common/error.h"
#include "engine/units.h"
#include "formats/json_file.h"
#include "util/sha256.h"
#include "util/text.h"

namespace napkin::formats {
namespace {

// "FILE line N: " starts every error of the readers.
std::string At(const std::filesystem::path& path, long line) {
  return util::EscapeControl(path.string()) + " line " + std::to_string(line) + ": ";
}

std::string ModelFileName(const std::filesystem::path& path) { return util::EscapeControl(path.string()); }

// A model file's lines, read through its descriptor from the start in chunks and hashed on the
// way: the file is never in memory, only the line being read. At its end the bytes read must be
// those ReadModelFile hashed, so a curve is always read from the bytes its rating names.
class ModelLines {
 public:
  explicit ModelLines(const ModelFile& file) : file_(file), buffer_(kChunkBytes) {}

  // The next line without its line end (LF or CRLF) into `line` and `number` counted on; false at
  // the end of the file (as std::getline: a last line without a line end is a line).
  bool Next(std::string& line, long& number) {
    line.clear();
    bool any = false;
    for (;;) {
      if (begin_ == end_ && !Fill()) {
        if (!any) return false;
        break;
      }
      any = true;
      const char* start = buffer_.data() + begin_;
      const void* newline = std::memchr(start, '\n', end_ - begin_);
      const std::size_t length = newline != nullptr
                                     ? static_cast<std::size_t>(static_cast<const char*>(newline) - start)
                                     : end_ - begin_;
      if (line.size() + length > kMaxModelLineBytes)
        throw InputError(At(file_.path, number + 1) + "the line is longer than the " +
                         std::to_string(kMaxModelLineBytes >> 20) +
                         " MiB napkin reads as one line of a model file.");
      line.append(start, length);
      begin_ += length;
      if (newline != nullptr) {
        ++begin_;
        break;
      }
    }
    if (!line.empty() && line.back() == '\r') line.pop_back();
    ++number;
    return true;
  }

 private:
  static constexpr std::size_t kChunkBytes = std::size_t{1} << 16;

  // The next chunk of the file into buffer_; false at its end, once its bytes are checked.
  bool Fill() {
    if (at_end_) return false;
    for (;;) {
      const ssize_t count =
          ::pread(file_.fd.get(), buffer_.data(), buffer_.size(), static_cast<off_t>(offset_));
      if (count < 0) {
        if (errno == EINTR) continue;
        throw InputError(ModelFileName(file_.path) + ": cannot be read (" + std::strerror(errno) + ").");
      }
      offset_ += static_cast<std::uintmax_t>(count);
      if (count == 0 || offset_ > kMaxModelFileBytes) {
        at_end_ = true;
        if (count != 0 || hash_.HexDigest() != file_.sha256)
          throw InputError(ModelFileName(file_.path) +
                           ": changed while napkin read it (its bytes are no longer those it opened); "
                           "rate it once it is written.");
        return false;
      }
      hash_.Update(std::string_view(buffer_.data(), static_cast<std::size_t>(count)));
      begin_ = 0;
      end_ = static_cast<std::size_t>(count);
      return true;
    }
  }

  const ModelFile& file_;
  std::vector<char> buffer_;
  std::size_t begin_ = 0, end_ = 0;  // the bytes of buffer_ not yet handed out
  std::uintmax_t offset_ = 0;        // of the file, after the bytes read
  bool at_end_ = false;
  util::Sha256 hash_;
};

// A curve's times, which must increase, checked as they are read. The first that does not is
// kept and thrown by Check once the curve's points are all read: after any error in its points,
// as when the times were checked after reading them all.
class IncreasingTimes {
 public:
  void Add(double time, long line) {
    if (count_ > 0 && failure_line_ == 0 && !(time > previous_)) {
      failure_line_ = line;
      failure_time_ = time;
      failure_previous_ = previous_;
    }
    previous_ = time;
    ++count_;
  }
  void Check(const std::filesystem::path& path) const {
    if (failure_line_ != 0)
      throw InputError(At(path, failure_line_) + "the time " + util::FormatNumber(failure_time_) +
                       " does not follow the previous one (" + util::FormatNumber(failure_previous_) +
                       "); times must increase.");
  }
  std::size_t count() const { return count_; }

 private:
  std::size_t count_ = 0;
  double previous_ = 0.0;
  long failure_line_ = 0;
  double failure_time_ = 0.0, failure_previous_ = 0.0;
};

// Refuses the point beyond kMaxModelCurvePoints of `curve` ("curve 7", "the file").
void CheckPointCount(std::size_t points, const std::filesystem::path& path, long line,
                     std::string_view curve) {
  if (points > kMaxModelCurvePoints)
    throw InputError(At(path, line) + std::string(curve) + " has more than " +
                     std::to_string(kMaxModelCurvePoints) + " points, the most napkin reads as one curve.");
}

// The numbers of a kept curve, read one by one into the Eigen vector the curve keeps: allocated
// once for the most points the file's bytes can hold (`capacity`, at most kMaxModelCurvePoints
// and one), which the system backs with memory only where a number is written, and cut to its
// length in place at the end (Eigen's conservativeResize reallocates, and a shrinking realloc
// keeps the block where it is). A std::vector's doubling held up to three times a curve's
// numbers while it grew and its copy into Eigen a second one (issue 42, point 14:
// bench/run_model_memory.sh measures the peak against the curve's bytes).
class CurveNumbers {
 public:
  CurveNumbers() = default;
  CurveNumbers(std::uintmax_t capacity, const std::filesystem::path& path)
      : numbers_(static_cast<Eigen::Index>(std::min<std::uintmax_t>(capacity, kMaxModelCurvePoints + 1))),
        path_(&path) {}

  void push_back(double value) {
    // More points than the file's bytes allowed when it was opened: it grew meanwhile.
    if (size_ == numbers_.size())
      throw InputError(ModelFileName(*path_) + " changed while it was being read; rate it again.");
    numbers_[size_++] = value;
  }
  // The numbers as the curve's vector, this buffer left empty; Copy leaves them here.
  Eigen::VectorXd Take() {
    numbers_.conservativeResize(size_);
    size_ = 0;
    return std::move(numbers_);
  }
  Eigen::VectorXd Copy() const { return numbers_.head(size_); }

 private:
  Eigen::VectorXd numbers_;
  Eigen::Index size_ = 0;
  const std::filesystem::path* path_ = nullptr;
};

// A nodout curve's numbers as one Eigen vector; `TakeVector` frees the numbers at once.
Eigen::VectorXd CopyVector(const std::vector<double>& numbers) {
  return Eigen::Map<const Eigen::VectorXd>(numbers.data(), static_cast<Eigen::Index>(numbers.size()));
}
Eigen::VectorXd TakeVector(std::vector<double>& numbers) {
  Eigen::VectorXd vector = CopyVector(numbers);
  std::vector<double>().swap(numbers);
  return vector;
}

// The model CSV's column suffixes: dimension and SI per unit.
struct CsvSuffix {
  std::string_view suffix;
  Dimension dimension;
  double si;
};
constexpr CsvSuffix kCsvSuffixes[] = {
    {"_mps2", kAccelerationDimension, 1.0},
    {"_radps2", kAngularAccelerationDimension, 1.0},
    {"_radps", kAngularVelocityDimension, 1.0},
    {"_degps", kAngularVelocityDimension, (1.0 / engine::kDegPerRad)},
    {"_mps", kVelocityDimension, 1.0},
    {"_mm", kLengthDimension, 1e-3},
    {"_m", kLengthDimension, 1.0},
    {"_rad", kAngleDimension, 1.0},
    {"_deg", kAngleDimension, (1.0 / engine::kDegPerRad)},
    {"_g", kAccelerationDimension, engine::kStandardGravity},
};

// Splits at commas (no quoting in model CSVs), trimming blanks: views into `line`.
void SplitCsvFields(std::string_view line, std::vector<std::string_view>& fields) {
  fields.clear();
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(util::Trim(line.substr(start, comma == std::string_view::npos ? comma : comma - start)));
    if (comma == std::string_view::npos) return;
    start = comma + 1;
  }
}

// The fields of an LS-DYNA card: comma-separated, or fixed columns of `width`; at least `count`
// (the missing ones empty). Views into `card`.
void CardFields(std::string_view card, std::size_t width, std::size_t count,
                std::vector<std::string_view>& fields) {
  if (card.find(',') != std::string_view::npos) {
    SplitCsvFields(card, fields);
  } else {
    fields.clear();
    for (std::size_t k = 0; k < count && k * width < card.size(); ++k)
      fields.push_back(util::Trim(card.substr(k * width, width)));
  }
  if (fields.size() < count) fields.resize(count);
}

// Every number of a nodout row: Fortran E fields may touch ("1.0E+00-2.0E+00").
void FortranNumbers(std::string_view text, std::vector<double>& numbers, bool& ok) {
  numbers.clear();
  ok = true;
  std::size_t k = 0;
  while (k < text.size()) {
    if (text[k] == ' ' || text[k] == '\t') {
      ++k;
      continue;
    }
    std::size_t end = k + 1;
    // A sign ends the number unless it follows an exponent letter.
    while (end < text.size() && text[end] != ' ' && text[end] != '\t' &&
           !((text[end] == '-' || text[end] == '+') && text[end - 1] != 'E' && text[end - 1] != 'e')) {
      ++end;
    }
    const std::optional<double> value = util::ParseDouble(text.substr(k, end - k));
    if (!value || !std::isfinite(*value)) {
      ok = false;
      return;
    }
    numbers.push_back(*value);
    k = end;
  }
}

KeepCurve KeepEvery() {
  return [](const std::string&) { return true; };
}

}  // namespace

ModelFile ReadModelFile(const std::filesystem::path& path) {
  // One descriptor, its type and size checked by fstat (formats/json_file.h), read through once
  // for the hash; the readers read it again from the same descriptor (ModelLines).
  ModelFile file{path, OpenRegularFile(path, kMaxModelFileBytes), {}, {}, 0};
  util::Sha256 hash;
  ReadDescriptorInChunks(file.fd.get(), kMaxModelFileBytes, ModelFileName(path) + ":",
                         "napkin reads from one model file", [&](std::string_view chunk) {
                           hash.Update(chunk);
                           file.bytes += chunk.size();
                           if (file.head.size() < kModelHeadBytes)
                             file.head.append(chunk.substr(0, kModelHeadBytes - file.head.size()));
                         });
  file.sha256 = hash.HexDigest();
  return file;
}

ModelUnits ParseModelUnits(std::string_view spec, std::string_view option) {
  static const std::map<std::string, double, std::less<>> kLength{{"m", 1.0},
                                                                  {"cm", 0.01},
                                                                  {"mm", 0.001},
                                                                  {"in", engine::kMetresPerInch},
                                                                  {"ft", engine::kMetresPerFoot}};
  static const std::map<std::string, double, std::less<>> kTime{{"s", 1.0}, {"ms", 1e-3}, {"us", 1e-6}};
  // lbf-s2/in: the mass one lbf accelerates at 1 in/s^2 (4.4482216152605 N / 0.0254 m/s^2).
  static const std::map<std::string, double, std::less<>> kMass{
      {"kg", 1.0}, {"g", 1e-3}, {"t", 1e3}, {"lbf-s2/in", 4.4482216152605 / engine::kMetresPerInch}};
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = spec.find(',', start);
    parts.push_back(util::ToLower(util::Trim(spec.substr(start, comma - start))));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  const auto length = parts.size() == 3 ? kLength.find(parts[0]) : kLength.end();
  const auto time = parts.size() == 3 ? kTime.find(parts[1]) : kTime.end();
  const auto mass = parts.size() == 3 ? kMass.find(parts[2]) : kMass.end();
  if (length == kLength.end() || time == kTime.end() || mass == kMass.end()) {
    throw UsageError(
        std::string(option) + " '" + util::EscapeControl(spec) +
        "' is not LENGTH,TIME,MASS with a length of m, cm, mm, in or ft, a time of s, ms or us and a "
        "mass of kg, g, t or lbf-s2/in (e.g. mm,ms,kg).");
  }
  return {length->second, time->second, mass->second};
}

double SiPerUnit(const ModelUnits& units, Dimension dimension) {
  return std::pow(units.metres, dimension.length) * std::pow(units.seconds, dimension.time) *
         std::pow(units.kilograms, dimension.mass);
}

ModelCurve ToSi(ModelCurve curve, Dimension dimension, const ModelUnits& units) {
  if (!curve.dimension) {
    curve.series.values *= SiPerUnit(units, dimension);
    curve.dimension = dimension;
  }
  return curve;
}

std::vector<ModelCurve> ReadModelCsv(const std::filesystem::path& path) {
  return ReadModelCsv(ReadModelFile(path));
}

bool ModelCsvColumnHasUnit(std::string_view name) {
  for (const CsvSuffix& suffix : kCsvSuffixes)
    if (name.size() > suffix.suffix.size() && name.ends_with(suffix.suffix)) return true;
  return false;
}

std::string ModelCsvUnitSuffixes() {
  std::string list;
  for (const CsvSuffix& suffix : kCsvSuffixes)
    list += (list.empty() ? "" : ", ") + std::string(suffix.suffix);
  return list;
}

std::vector<ModelCurve> ReadModelCsv(const ModelFile& file) { return ReadModelCsv(file, KeepEvery()).kept; }

ModelCurves ReadModelCsv(const ModelFile& file, const KeepCurve& keep) {
  const std::filesystem::path& path = file.path;
  ModelLines in(file);
  std::string line;
  long number = 0;
  std::vector<std::string_view> fields;
  std::vector<std::string> header;
  while (in.Next(line, number)) {
    if (util::Trim(line).empty() || line[0] == '#') continue;
    SplitCsvFields(line, fields);
    header.assign(fields.begin(), fields.end());
    break;
  }
  if (header.empty())
    throw InputError(At(path, number) + "the file ends before its header (time_s and columns).");
  const long header_line = number;
  std::optional<std::size_t> time_column;
  double time_scale = 1.0;
  for (std::size_t c = 0; c < header.size(); ++c) {
    if (header[c] == "time_s" || header[c] == "time_ms") {
      if (time_column) {
        throw InputError(At(path, header_line) + "the header has two time columns ('" + header[*time_column] +
                         "' and '" + header[c] + "').");
      }
      time_column = c;
      time_scale = header[c] == "time_ms" ? 1e-3 : 1.0;
    } else if (header[c].empty()) {
      throw InputError(At(path, header_line) + "column " + std::to_string(c + 1) +
                       " of the header has no name.");
    }
  }
  if (!time_column) throw InputError(At(path, header_line) + "the header has no time_s (or time_ms) column.");
  // Per column what decides whether it is a curve and whether it is whole; the numbers of the
  // columns kept only.
  struct Column {
    Dimension dimension{};
    double si = 1.0;
    bool kept = false;
    CurveNumbers values;  // kept: SI, NaN where empty
    std::size_t empty = 0;
    long first_empty_line = 0;
  };
  std::vector<Column> columns(header.size());
  bool any_kept = false;
  for (std::size_t c = 0; c < header.size(); ++c) {
    if (c == *time_column) continue;
    for (const CsvSuffix& suffix : kCsvSuffixes) {
      if (header[c].size() > suffix.suffix.size() && header[c].ends_with(suffix.suffix)) {
        columns[c].dimension = suffix.dimension;
        columns[c].si = suffix.si;
        break;
      }
    }
    columns[c].kept = keep(header[c]);
    any_kept = any_kept || columns[c].kept;
  }
  // A row holds at least a comma between each two fields and its line's end: the most rows the
  // file can hold, for the kept columns' numbers (CurveNumbers).
  const std::uintmax_t most_rows = file.bytes / header.size() + 1;
  for (Column& column : columns)
    if (column.kept) column.values = CurveNumbers(most_rows, path);
  CurveNumbers time_s = any_kept ? CurveNumbers(most_rows, path) : CurveNumbers();  // when a column is kept
  IncreasingTimes times;
  std::size_t rows = 0;
  long first_empty_time_line = 0;
  while (in.Next(line, number)) {
    if (util::Trim(line).empty() || line[0] == '#') continue;
    SplitCsvFields(line, fields);
    if (fields.size() != header.size()) {
      throw InputError(At(path, number) + "the row has " + std::to_string(fields.size()) +
                       " fields, but the header has " + std::to_string(header.size()) + ".");
    }
    for (std::size_t c = 0; c < fields.size(); ++c) {
      Column& column = columns[c];
      const bool is_time = c == *time_column;
      if (fields[c].empty()) {
        if (is_time && first_empty_time_line == 0) first_empty_time_line = number;
        if (column.empty++ == 0) column.first_empty_line = number;
        if (is_time ? any_kept : column.kept) (is_time ? time_s : column.values).push_back(std::nan(""));
        continue;
      }
      const std::optional<double> value = util::ParseDouble(fields[c]);
      if (!value || !std::isfinite(*value)) {
        throw InputError(At(path, number) + "column '" + util::EscapeControl(header[c]) + "' holds '" +
                         util::EscapeControl(fields[c]) + "', which is not a finite number.");
      }
      if (is_time) {
        const double t = *value * time_scale;
        times.Add(t, number);
        if (any_kept) time_s.push_back(t);
      } else if (column.kept) {
        column.values.push_back(*value * column.si);
      }
    }
    CheckPointCount(++rows, path, number, "the file");
  }
  if (rows < 2) throw InputError(At(path, number) + "the file has fewer than 2 rows of samples.");
  if (first_empty_time_line != 0) throw InputError(At(path, first_empty_time_line) + "the time is empty.");
  times.Check(path);
  ModelCurves curves;
  // The last kept column takes the time's numbers; the others copy them.
  std::optional<std::size_t> last_kept;
  for (std::size_t c = 0; c < header.size(); ++c)
    if (c != *time_column && columns[c].kept && columns[c].empty != rows) last_kept = c;
  for (std::size_t c = 0; c < header.size(); ++c) {
    if (c == *time_column) continue;
    Column& column = columns[c];
    if (column.empty == rows) continue;  // a channel the file does not have
    if (column.empty > 0) {
      throw InputError(At(path, column.first_empty_line) + "column '" + util::EscapeControl(header[c]) +
                       "' is empty, but other rows have a value there.");
    }
    curves.names.push_back(header[c]);
    if (column.kept)
      curves.kept.push_back({header[c],
                             column.dimension,
                             {c == last_kept ? time_s.Take() : time_s.Copy(), column.values.Take()}});
  }
  if (curves.names.empty())
    throw InputError(At(path, header_line) + "the header names no column besides the time.");
  return curves;
}

std::vector<ModelCurve> ReadLsDynaCurves(const std::filesystem::path& path, const ModelUnits& units) {
  return ReadLsDynaCurves(ReadModelFile(path), units);
}

std::vector<ModelCurve> ReadLsDynaCurves(const ModelFile& file, const ModelUnits& units) {
  return ReadLsDynaCurves(file, units, KeepEvery()).kept;
}

ModelCurves ReadLsDynaCurves(const ModelFile& file, const ModelUnits& units, const KeepCurve& keep) {
  const std::filesystem::path& path = file.path;
  ModelLines in(file);
  std::string line;
  long number = 0;
  ModelCurves curves;
  std::vector<std::string_view> card, point;
  bool pending = in.Next(line, number);
  while (pending) {
    const std::string_view trimmed = util::Trim(line);
    if (!trimmed.starts_with('*')) {
      pending = in.Next(line, number);
      continue;
    }
    const std::string keyword = util::ToUpper(trimmed);
    if (!keyword.starts_with("*DEFINE_CURVE") ||
        (keyword != "*DEFINE_CURVE" && keyword != "*DEFINE_CURVE_TITLE")) {
      pending = in.Next(line, number);
      continue;
    }
    const long keyword_line = number;
    std::string title;
    auto next_card = [&]() {
      while ((pending = in.Next(line, number))) {
        if (!line.empty() && line[0] == '$') continue;
        return !line.empty() && line[0] != '*';
      }
      return false;
    };
    if (keyword == "*DEFINE_CURVE_TITLE") {
      if (!next_card()) throw InputError(At(path, number) + "*DEFINE_CURVE_TITLE has no title card.");
      title = std::string(util::Trim(line));
    }
    if (!next_card()) {
      throw InputError(At(path, keyword_line) + "the *DEFINE_CURVE has no card with its LCID.");
    }
    const long card_line = number;
    CardFields(line, 10, 7, card);
    const std::string lcid_text(card[0]);  // `card` views the line, which the points replace
    auto number_of = [&](std::size_t k, const char* name, double fallback) {
      if (card[k].empty()) return fallback;
      const std::optional<double> value = util::ParseDouble(card[k]);
      if (!value || !std::isfinite(*value)) {
        throw InputError(At(path, card_line) + name + " '" + util::EscapeControl(card[k]) +
                         "' is not a number.");
      }
      return *value;
    };
    const double lcid = number_of(0, "LCID", std::nan(""));
    if (!std::isfinite(lcid) || lcid != std::floor(lcid)) {
      throw InputError(At(path, card_line) + "the *DEFINE_CURVE has no integer LCID.");
    }
    double sfa = number_of(2, "SFA", 1.0), sfo = number_of(3, "SFO", 1.0);
    if (sfa == 0.0) sfa = 1.0;  // LS-DYNA reads 0 as the default 1
    if (sfo == 0.0) sfo = 1.0;
    if (number_of(4, "OFFA", 0.0) != 0.0 || number_of(5, "OFFO", 0.0) != 0.0) {
      throw InputError(At(path, card_line) + "curve " + lcid_text +
                       " has an offset (OFFA or OFFO), which napkin does not read; write it without.");
    }
    std::string name = "curve " + util::FormatNumber(lcid);
    if (!title.empty()) name += " " + title;
    const bool kept = keep(name);
    const std::string curve_text = "curve " + lcid_text;
    // A point's line holds at least two numbers, a separator and its end: the most points the rest
    // of the file can hold, for the kept curve's numbers (CurveNumbers).
    const std::uintmax_t most_points = file.bytes / 4 + 1;
    CurveNumbers time_s = kept ? CurveNumbers(most_points, path) : CurveNumbers();
    CurveNumbers values = kept ? CurveNumbers(most_points, path) : CurveNumbers();
    IncreasingTimes times;
    while (next_card()) {
      CardFields(line, 20, 2, point);
      const std::optional<double> a = util::ParseDouble(point[0]);
      const std::optional<double> o = util::ParseDouble(point[1]);
      if (!a || !o || !std::isfinite(*a) || !std::isfinite(*o)) {
        throw InputError(At(path, number) + curve_text + "'s point '" +
                         util::EscapeControl(util::Trim(line)) +
                         "' is not two numbers (abscissa, ordinate).");
      }
      const double t = *a * sfa * units.seconds;
      times.Add(t, number);
      CheckPointCount(times.count(), path, number, curve_text);
      if (kept) {
        time_s.push_back(t);
        values.push_back(*o * sfo);
      }
    }
    if (times.count() < 2) throw InputError(At(path, card_line) + curve_text + " has fewer than 2 points.");
    times.Check(path);
    curves.names.push_back(name);
    if (kept) curves.kept.push_back({name, std::nullopt, {time_s.Take(), values.Take()}});
  }
  if (curves.names.empty()) throw InputError(At(path, number) + "the keyword file has no *DEFINE_CURVE.");
  return curves;
}

namespace {

// The quantity of each nodout column.
const std::map<std::string, Dimension, std::less<>>& NodoutColumns() {
  static const std::map<std::string, Dimension, std::less<>> kColumns{
      {"x-disp", kLengthDimension},
      {"y-disp", kLengthDimension},
      {"z-disp", kLengthDimension},
      {"x-vel", kVelocityDimension},
      {"y-vel", kVelocityDimension},
      {"z-vel", kVelocityDimension},
      {"x-accl", kAccelerationDimension},
      {"y-accl", kAccelerationDimension},
      {"z-accl", kAccelerationDimension},
      {"x-coor", kLengthDimension},
      {"y-coor", kLengthDimension},
      {"z-coor", kLengthDimension},
      {"x-rot", kAngleDimension},
      {"y-rot", kAngleDimension},
      {"z-rot", kAngleDimension},
      {"x-rot-vel", kAngularVelocityDimension},
      {"y-rot-vel", kAngularVelocityDimension},
      {"z-rot-vel", kAngularVelocityDimension},
      {"x-rot-acc", kAngularAccelerationDimension},
      {"y-rot-acc", kAngularAccelerationDimension},
      {"z-rot-acc", kAngularAccelerationDimension}};
  return kColumns;
}

std::string NodeCurveName(long node, const std::string& column) {
  return "node " + std::to_string(node) + " " + column;
}

// A nodout as read: its curves, and for the sentence about a missing node the first block's
// line and the nodes of the first kind (translational when the file has both).
struct NodoutRead {
  ModelCurves curves;
  long first_block_line = 0;
  std::vector<long> first_nodes;
};

NodoutRead ReadNodoutBlocks(const ModelFile& file, const ModelUnits& units, const KeepCurve& keep) {
  const std::filesystem::path& path = file.path;
  const std::map<std::string, Dimension, std::less<>>& kColumns = NodoutColumns();
  ModelLines in(file);
  std::string line;
  long number = 0;
  // The blocks of one kind (translational, rotational): the columns and nodes of its first block,
  // which every other block of it repeats, its times, and the numbers of the curves kept.
  struct Kind {
    long first_line = 0;
    std::vector<std::string> columns;
    std::vector<long> nodes;
    IncreasingTimes times;
    std::vector<double> time_s;               // when a curve of the kind is kept
    std::vector<std::ptrdiff_t> slot;         // per node and column: into `values`, or -1
    std::vector<std::vector<double>> values;  // SI
  };
  std::map<bool, Kind> kinds;  // false: translational
  std::vector<long> block_nodes;
  std::vector<double> row;
  bool have = in.Next(line, number);
  while (have) {
    const std::size_t at = line.find("( at time");
    if (line.find("n o d a l") == std::string::npos || at == std::string::npos) {
      have = in.Next(line, number);
      continue;
    }
    const std::size_t close = line.find(')', at);
    const std::optional<double> time = util::ParseDouble(
        std::string_view(line).substr(at + 9, close == std::string::npos ? close : close - at - 9));
    if (!time || !std::isfinite(*time)) {
      throw InputError(At(path, number) + "the block's time '" + util::EscapeControl(line.substr(at)) +
                       "' is not a number.");
    }
    const long block_line = number;
    // The header of column names, after blank lines.
    while ((have = in.Next(line, number)) && util::Trim(line).empty()) {
    }
    std::string header = have ? line : std::string();
    for (const char* axis : {"x", "y", "z"}) {
      for (const char* kind : {"vel", "acc"}) {
        const std::string spaced = std::string(axis) + "-rot " + kind;
        for (std::size_t p = header.find(spaced); p != std::string::npos; p = header.find(spaced))
          header[p + 5] = '-';
      }
    }
    std::vector<std::string> columns;
    {
      std::size_t k = 0;
      const std::string_view h(header);
      while (k < h.size()) {
        while (k < h.size() && h[k] == ' ') ++k;
        std::size_t end = k;
        while (end < h.size() && h[end] != ' ') ++end;
        if (end > k) columns.emplace_back(h.substr(k, end - k));
        k = end;
      }
    }
    if (columns.size() < 3 || columns[0] != "nodal" || columns[1] != "point") {
      throw InputError(At(path, number) + "the line after the block header of line " +
                       std::to_string(block_line) + " is not the column names (\"nodal point x-disp ...\").");
    }
    columns.erase(columns.begin(), columns.begin() + 2);
    for (const std::string& column : columns) {
      if (!kColumns.contains(column)) {
        throw InputError(At(path, number) + "the column '" + util::EscapeControl(column) +
                         "' is not a nodout column.");
      }
    }
    const bool rotational = columns[0].find("rot") != std::string::npos;
    for (std::size_t c = 0; c < columns.size(); ++c) {
      // A column twice, or of the other kind, would make two curves of one name.
      if (std::find(columns.begin(), columns.begin() + static_cast<std::ptrdiff_t>(c), columns[c]) !=
          columns.begin() + static_cast<std::ptrdiff_t>(c))
        throw InputError(At(path, number) + "the column '" + columns[c] + "' is named twice.");
      if ((columns[c].find("rot") != std::string::npos) != rotational)
        throw InputError(At(path, number) + "the block mixes rotational and translational columns ('" +
                         columns[0] + "' and '" + columns[c] + "').");
    }
    Kind& kind = kinds[rotational];
    const bool first_of_kind = kind.times.count() == 0;
    if (first_of_kind) {
      kind.first_line = block_line;
      kind.columns = columns;
    } else if (columns != kind.columns) {
      throw InputError(At(path, number) +
                       "the columns are not those of the first block of their kind (line " +
                       std::to_string(kind.first_line) + ").");
    }
    kind.times.Add(*time * units.seconds, block_line);
    CheckPointCount(kind.times.count(), path, block_line, "the file");
    if (first_of_kind || !kind.values.empty()) kind.time_s.push_back(*time * units.seconds);
    std::vector<double> si(columns.size());
    for (std::size_t c = 0; c < columns.size(); ++c) si[c] = SiPerUnit(units, kColumns.at(columns[c]));
    block_nodes.clear();
    // Rows up to a blank line or the next block (which the outer loop reads).
    while ((have = in.Next(line, number)) && !util::Trim(line).empty() &&
           line.find("n o d a l") == std::string::npos) {
      bool ok = true;
      FortranNumbers(line, row, ok);
      if (!ok || row.size() != columns.size() + 1 || row[0] != std::floor(row[0])) {
        throw InputError(At(path, number) + "the row is not a node id and " + std::to_string(columns.size()) +
                         " numbers.");
      }
      const auto id = static_cast<long>(row[0]);
      const std::size_t index = block_nodes.size();
      block_nodes.push_back(id);
      if (first_of_kind) {
        if (std::find(kind.nodes.begin(), kind.nodes.end(), id) != kind.nodes.end())
          throw InputError(At(path, number) + "the block lists node " + std::to_string(id) + " twice.");
        kind.nodes.push_back(id);
        for (const std::string& column : columns) {
          kind.slot.push_back(-1);
          if (keep(NodeCurveName(id, column))) {
            kind.slot.back() = static_cast<std::ptrdiff_t>(kind.values.size());
            kind.values.emplace_back();
          }
        }
      }
      if (index >= kind.nodes.size()) continue;  // another node than the first block's: said below
      for (std::size_t c = 0; c < columns.size(); ++c) {
        const std::ptrdiff_t slot = kind.slot[index * columns.size() + c];
        if (slot >= 0) kind.values[static_cast<std::size_t>(slot)].push_back(row[c + 1] * si[c]);
      }
    }
    if (first_of_kind) {
      if (kind.values.empty()) std::vector<double>().swap(kind.time_s);  // no curve of the kind kept
    } else if (block_nodes != kind.nodes) {
      throw InputError(At(path, block_line) +
                       "the block lists other nodes than the first block of its kind.");
    }
  }
  if (kinds.empty())
    throw InputError(At(path, number) + "the file has no nodout block (\"n o d a l   p r i n t\").");
  for (const auto& [rotational, kind] : kinds) kind.times.Check(path);
  // The curves by node, then column name.
  struct Curve {
    long node;
    const std::string* column;
    Kind* kind;
    std::ptrdiff_t slot;
  };
  std::vector<Curve> all;
  for (auto& [rotational, kind] : kinds)
    for (std::size_t n = 0; n < kind.nodes.size(); ++n)
      for (std::size_t c = 0; c < kind.columns.size(); ++c)
        all.push_back({kind.nodes[n], &kind.columns[c], &kind, kind.slot[n * kind.columns.size() + c]});
  std::sort(all.begin(), all.end(), [](const Curve& a, const Curve& b) {
    return std::tie(a.node, *a.column) < std::tie(b.node, *b.column);
  });
  NodoutRead read;
  read.first_block_line = std::min_element(kinds.begin(), kinds.end(), [](const auto& a, const auto& b) {
                            return a.second.first_line < b.second.first_line;
                          })->second.first_line;
  read.first_nodes = kinds.begin()->second.nodes;
  for (const Curve& curve : all) {
    std::string name = NodeCurveName(curve.node, *curve.column);
    if (curve.slot >= 0)
      read.curves.kept.push_back({name,
                                  kColumns.at(*curve.column),
                                  {CopyVector(curve.kind->time_s),
                                   TakeVector(curve.kind->values[static_cast<std::size_t>(curve.slot)])}});
    read.curves.names.push_back(std::move(name));
  }
  return read;
}

}  // namespace

std::vector<ModelCurve> ReadNodout(const std::filesystem::path& path, const ModelUnits& units,
                                   std::optional<long> node) {
  return ReadNodout(ReadModelFile(path), units, node);
}

std::vector<ModelCurve> ReadNodout(const ModelFile& file, const ModelUnits& units, std::optional<long> node) {
  const std::string prefix = node ? NodeCurveName(*node, "") : std::string();
  NodoutRead read =
      ReadNodoutBlocks(file, units, [&](const std::string& name) { return name.starts_with(prefix); });
  if (read.curves.kept.empty()) {
    std::string listed;
    for (long id : read.first_nodes) listed += (listed.empty() ? "" : ", ") + std::to_string(id);
    throw InputError(At(file.path, read.first_block_line) + "the nodout has no node " +
                     std::to_string(node.value_or(0)) + " (its first block lists " + listed + ").");
  }
  return std::move(read.curves.kept);
}

ModelCurves ReadNodout(const ModelFile& file, const ModelUnits& units, const KeepCurve& keep) {
  return ReadNodoutBlocks(file, units, keep).curves;
}

}  // namespace napkin::formats
