#include "formats/model_curves.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
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

// Reads one line without its line end (LF or CRLF).
bool NextLine(std::istringstream& in, std::string& line, long& number) {
  if (!std::getline(in, line)) return false;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  ++number;
  return true;
}

void CheckTimes(const std::filesystem::path& path, const std::vector<double>& times,
                const std::vector<long>& lines) {
  for (std::size_t k = 1; k < times.size(); ++k) {
    if (!(times[k] > times[k - 1])) {
      throw InputError(At(path, lines[k]) + "the time " + util::FormatNumber(times[k]) +
                       " does not follow the previous one (" + util::FormatNumber(times[k - 1]) +
                       "); times must increase.");
    }
  }
}

engine::TimeSeries Series(const std::vector<double>& time_s, const std::vector<double>& values) {
  engine::TimeSeries series{Eigen::VectorXd(static_cast<Eigen::Index>(time_s.size())),
                            Eigen::VectorXd(static_cast<Eigen::Index>(values.size()))};
  for (std::size_t k = 0; k < time_s.size(); ++k) {
    series.time_s(static_cast<Eigen::Index>(k)) = time_s[k];
    series.values(static_cast<Eigen::Index>(k)) = values[k];
  }
  return series;
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

// Splits at commas (no quoting in model CSVs), trimming blanks.
std::vector<std::string> CsvFields(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    fields.emplace_back(util::Trim(std::string_view(line).substr(start, comma - start)));
    if (comma == std::string::npos) return fields;
    start = comma + 1;
  }
}

// Every number of a nodout row: Fortran E fields may touch ("1.0E+00-2.0E+00").
std::vector<double> FortranNumbers(std::string_view text, bool& ok) {
  std::vector<double> numbers;
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
      return numbers;
    }
    numbers.push_back(*value);
    k = end;
  }
  return numbers;
}

}  // namespace

ModelFile ReadModelFile(const std::filesystem::path& path) {
  // One descriptor, its type checked by fstat, its size bounded (formats/json_file.h): a model's
  // bytes and the curves parsed from them are all in memory at once (10^7 points took 1.26 GB).
  std::string bytes = ReadWholeFile(path, kMaxModelFileBytes);
  std::string sha256 = util::Sha256Hex(bytes);
  return {path, std::move(bytes), std::move(sha256)};
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

std::vector<ModelCurve> ReadModelCsv(const ModelFile& file) {
  const std::filesystem::path& path = file.path;
  std::istringstream in(file.bytes);
  std::string line;
  long number = 0;
  std::vector<std::string> header;
  while (NextLine(in, line, number)) {
    if (util::Trim(line).empty() || line[0] == '#') continue;
    header = CsvFields(line);
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
  std::vector<std::vector<std::optional<double>>> cells(header.size());
  std::vector<long> lines;
  while (NextLine(in, line, number)) {
    if (util::Trim(line).empty() || line[0] == '#') continue;
    const std::vector<std::string> fields = CsvFields(line);
    if (fields.size() != header.size()) {
      throw InputError(At(path, number) + "the row has " + std::to_string(fields.size()) +
                       " fields, but the header has " + std::to_string(header.size()) + ".");
    }
    for (std::size_t c = 0; c < fields.size(); ++c) {
      if (fields[c].empty()) {
        cells[c].push_back(std::nullopt);
        continue;
      }
      const std::optional<double> value = util::ParseDouble(fields[c]);
      if (!value || !std::isfinite(*value)) {
        throw InputError(At(path, number) + "column '" + util::EscapeControl(header[c]) + "' holds '" +
                         util::EscapeControl(fields[c]) + "', which is not a finite number.");
      }
      cells[c].push_back(value);
    }
    lines.push_back(number);
  }
  if (lines.size() < 2) throw InputError(At(path, number) + "the file has fewer than 2 rows of samples.");
  std::vector<double> time_s;
  for (std::size_t r = 0; r < lines.size(); ++r) {
    if (!cells[*time_column][r]) throw InputError(At(path, lines[r]) + "the time is empty.");
    time_s.push_back(*cells[*time_column][r] * time_scale);
  }
  CheckTimes(path, time_s, lines);
  std::vector<ModelCurve> curves;
  for (std::size_t c = 0; c < header.size(); ++c) {
    if (c == *time_column) continue;
    const auto empty = std::count(cells[c].begin(), cells[c].end(), std::nullopt);
    if (empty == static_cast<long>(lines.size())) continue;  // a channel the file does not have
    if (empty > 0) {
      const auto r = static_cast<std::size_t>(std::find(cells[c].begin(), cells[c].end(), std::nullopt) -
                                              cells[c].begin());
      throw InputError(At(path, lines[r]) + "column '" + util::EscapeControl(header[c]) +
                       "' is empty, but other rows have a value there.");
    }
    Dimension dimension{};
    double si = 1.0;
    for (const CsvSuffix& suffix : kCsvSuffixes) {
      if (header[c].size() > suffix.suffix.size() && header[c].ends_with(suffix.suffix)) {
        dimension = suffix.dimension;
        si = suffix.si;
        break;
      }
    }
    std::vector<double> values;
    for (const std::optional<double>& cell : cells[c]) values.push_back(*cell * si);
    curves.push_back({header[c], dimension, Series(time_s, values)});
  }
  if (curves.empty())
    throw InputError(At(path, header_line) + "the header names no column besides the time.");
  return curves;
}

std::vector<ModelCurve> ReadLsDynaCurves(const std::filesystem::path& path, const ModelUnits& units) {
  return ReadLsDynaCurves(ReadModelFile(path), units);
}

std::vector<ModelCurve> ReadLsDynaCurves(const ModelFile& file, const ModelUnits& units) {
  const std::filesystem::path& path = file.path;
  std::istringstream in(file.bytes);
  std::string line;
  long number = 0;
  std::vector<ModelCurve> curves;
  // Fields of a card: comma-separated, or fixed columns of `width`.
  auto fields = [](const std::string& card, std::size_t width, std::size_t count) {
    std::vector<std::string> out;
    if (card.find(',') != std::string::npos) {
      for (std::string& field : CsvFields(card)) out.push_back(std::move(field));
    } else {
      for (std::size_t k = 0; k < count && k * width < card.size(); ++k)
        out.emplace_back(util::Trim(std::string_view(card).substr(k * width, width)));
    }
    out.resize(std::max(out.size(), count));
    return out;
  };
  bool pending = NextLine(in, line, number);
  while (pending) {
    const std::string keyword = util::ToUpper(util::Trim(line));
    if (!keyword.starts_with("*DEFINE_CURVE") ||
        (keyword != "*DEFINE_CURVE" && keyword != "*DEFINE_CURVE_TITLE")) {
      pending = NextLine(in, line, number);
      continue;
    }
    const long keyword_line = number;
    std::string title;
    auto next_card = [&]() {
      while ((pending = NextLine(in, line, number))) {
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
    const std::vector<std::string> card = fields(line, 10, 7);
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
      throw InputError(At(path, card_line) + "curve " + card[0] +
                       " has an offset (OFFA or OFFO), which napkin does not read; write it without.");
    }
    std::vector<double> time_s, values;
    std::vector<long> lines;
    while (next_card()) {
      const std::vector<std::string> point = fields(line, 20, 2);
      const std::optional<double> a = util::ParseDouble(point[0]);
      const std::optional<double> o = util::ParseDouble(point[1]);
      if (!a || !o || !std::isfinite(*a) || !std::isfinite(*o)) {
        throw InputError(At(path, number) + "curve " + card[0] + "'s point '" +
                         util::EscapeControl(util::Trim(line)) +
                         "' is not two numbers (abscissa, ordinate).");
      }
      time_s.push_back(*a * sfa * units.seconds);
      values.push_back(*o * sfo);
      lines.push_back(number);
    }
    if (time_s.size() < 2)
      throw InputError(At(path, card_line) + "curve " + card[0] + " has fewer than 2 points.");
    CheckTimes(path, time_s, lines);
    std::string name = "curve " + util::FormatNumber(lcid);
    if (!title.empty()) name += " " + title;
    curves.push_back({name, std::nullopt, Series(time_s, values)});
  }
  if (curves.empty()) throw InputError(At(path, number) + "the keyword file has no *DEFINE_CURVE.");
  return curves;
}

std::vector<ModelCurve> ReadNodout(const std::filesystem::path& path, const ModelUnits& units,
                                   std::optional<long> node) {
  return ReadNodout(ReadModelFile(path), units, node);
}

std::vector<ModelCurve> ReadNodout(const ModelFile& file, const ModelUnits& units, std::optional<long> node) {
  const std::filesystem::path& path = file.path;
  std::istringstream in(file.bytes);
  std::string line;
  long number = 0;
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
  // (node, column) -> values; per block kind (translational, rotational) the times.
  std::map<std::pair<long, std::string>, std::vector<double>> values;
  std::map<bool, std::vector<double>> times;
  std::map<bool, std::vector<long>> time_lines;
  std::map<bool, std::vector<long>> nodes_of_kind;
  bool any_block = false;
  long first_block_line = 0;
  bool have = NextLine(in, line, number);
  while (have) {
    const std::size_t at = line.find("( at time");
    if (line.find("n o d a l") == std::string::npos || at == std::string::npos) {
      have = NextLine(in, line, number);
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
    if (!any_block) first_block_line = number;
    // The header of column names, after blank lines.
    while ((have = NextLine(in, line, number)) && util::Trim(line).empty()) {
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
    times[rotational].push_back(*time * units.seconds);
    time_lines[rotational].push_back(block_line);
    std::vector<long> block_nodes;
    // Rows up to a blank line or the next block (which the outer loop reads).
    while ((have = NextLine(in, line, number)) && !util::Trim(line).empty() &&
           line.find("n o d a l") == std::string::npos) {
      bool ok = true;
      const std::vector<double> row = FortranNumbers(line, ok);
      if (!ok || row.size() != columns.size() + 1 || row[0] != std::floor(row[0])) {
        throw InputError(At(path, number) + "the row is not a node id and " + std::to_string(columns.size()) +
                         " numbers.");
      }
      const auto id = static_cast<long>(row[0]);
      block_nodes.push_back(id);
      if (node && id != *node) continue;
      for (std::size_t c = 0; c < columns.size(); ++c) {
        values[{id, columns[c]}].push_back(row[c + 1] * SiPerUnit(units, kColumns.at(columns[c])));
      }
    }
    if (times[rotational].size() == 1) {
      nodes_of_kind[rotational] = block_nodes;
    } else if (block_nodes != nodes_of_kind[rotational]) {
      throw InputError(At(path, block_line) +
                       "the block lists other nodes than the first block of its kind.");
    }
    any_block = true;
  }
  if (!any_block)
    throw InputError(At(path, number) + "the file has no nodout block (\"n o d a l   p r i n t\").");
  for (auto& [kind, t] : times) CheckTimes(path, t, time_lines[kind]);
  std::vector<ModelCurve> curves;
  for (const auto& [key, v] : values) {
    const bool rotational = key.second.find("rot") != std::string::npos;
    curves.push_back({"node " + std::to_string(key.first) + " " + key.second, kColumns.at(key.second),
                      Series(times[rotational], v)});
  }
  if (curves.empty()) {
    std::string listed;
    for (long id : nodes_of_kind.begin()->second) listed += (listed.empty() ? "" : ", ") + std::to_string(id);
    throw InputError(At(path, first_block_line) + "the nodout has no node " +
                     std::to_string(node.value_or(0)) + " (its first block lists " + listed + ").");
  }
  return curves;
}

}  // namespace napkin::formats
