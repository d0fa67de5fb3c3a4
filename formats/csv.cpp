#include "formats/csv.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <type_traits>

#include "common/error.h"
#include "engine/units.h"
#include "formats/json_file.h"
#include "util/atomic_file.h"
#include "util/text.h"

namespace napkin::formats {
namespace {

// Relative tolerance on the sampling interval (docs/formats.md).
constexpr double kMaxRelativeJitter = 1e-6;
// Longest line (header or row) and the number of ignored columns named one
// by one in the warning (docs/formats.md "Names, limits and escaping").
constexpr std::size_t kMaxLineBytes = std::size_t{1} << 20;
constexpr std::size_t kIgnoredColumnsNamed = 5;

// Splits `line` at commas into `fields` (views into `line`).
void SplitFields(std::string_view line, std::vector<std::string_view>& fields) {
  fields.clear();
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    if (comma == std::string_view::npos) {
      fields.push_back(line.substr(start));
      return;
    }
    fields.push_back(line.substr(start, comma - start));
    start = comma + 1;
  }
}

// The ignored columns of the warning: the first kIgnoredColumnsNamed quoted, then how many more
// ("a", "b", "c", "d", "e" and 3 more).
std::string IgnoredColumnNames(const std::vector<std::string_view>& ignored) {
  std::string names;
  for (std::size_t i = 0; i < ignored.size() && i < kIgnoredColumnsNamed; ++i) {
    if (i > 0) names += ", ";
    names += util::Quoted(ignored[i]);
  }
  if (ignored.size() > kIgnoredColumnsNamed)
    names += " and " + std::to_string(ignored.size() - kIgnoredColumnsNamed) + " more";
  return names;
}

std::string_view Unquote(std::string_view text) {
  text = util::Trim(text);
  if (text.size() >= 2 && text.front() == '"' && text.back() == '"')
    text = util::Trim(text.substr(1, text.size() - 2));
  return text;
}

// Input quoted in a message: escaped and cut (util/text.h Abbreviated).
// The column `slot` is read from: its mapping in `columns`, else its own name.
const std::string& ColumnOf(const std::string& slot, const CsvColumnMap& columns) {
  for (const auto& [mapped_slot, column] : columns)
    if (mapped_slot == slot) return column;
  return slot;
}

std::string ColumnDescription(const std::string& slot, const CsvColumnMap& columns) {
  const std::string& column = ColumnOf(slot, columns);
  if (column == slot) return "no column for slot " + util::Quoted(slot);
  return "no column " + util::Quoted(column) + " (mapped to slot " + util::Quoted(slot) + ")";
}

}  // namespace

CsvColumnMap ParseCsvColumnOptions(const std::vector<std::string>& options) {
  CsvColumnMap columns;
  for (const std::string& option : options) {
    const std::size_t equals = option.find('=');
    const std::string slot =
        equals == std::string::npos ? "" : std::string(util::Trim(option.substr(0, equals)));
    const std::string column =
        equals == std::string::npos ? "" : std::string(util::Trim(option.substr(equals + 1)));
    if (slot.empty() || column.empty())
      throw UsageError("--column takes SLOT=NAME (the CSV column NAME feeds slot SLOT), not " +
                       util::Quoted(option) + ".");
    for (const auto& [earlier, unused] : columns)
      if (earlier == slot) throw UsageError("--column maps slot " + util::Quoted(slot) + " twice.");
    columns.emplace_back(slot, column);
  }
  return columns;
}

void RefuseNonFiniteSample(const std::string& where, std::string_view written) {
  throw InputError(where + ": " + util::Quoted(written) + " is not a finite number.");
}

void CheckSampleCount(std::size_t samples, const std::string& source, std::string_view unit) {
  if (samples < 2)
    throw InputError(source + ": has " + std::to_string(samples) + " " + std::string(unit) +
                     (samples == 1 ? "" : "s") + ", at least two are needed.");
}

TimeBase UniformTimeBase(std::span<const double> time_s, const std::string& source,
                         const std::function<std::string(std::size_t)>& sample_name, std::string_view noun) {
  // Strictly increasing, then uniformly spaced around the mean interval.
  for (std::size_t k = 1; k < time_s.size(); ++k)
    if (!(time_s[k] > time_s[k - 1]))
      throw InputError(source + ": " + sample_name(k) + ": time_s " + util::FormatNumber(time_s[k]) +
                       " does not increase over the previous " + std::string(noun) + "'s " +
                       util::FormatNumber(time_s[k - 1]) + ".");
  const double dt = (time_s.back() - time_s.front()) / static_cast<double>(time_s.size() - 1);
  if (!(std::isfinite(dt) && dt > 0.0))
    throw InputError(source + ": time_s runs from " + util::FormatNumber(time_s.front()) + " s to " +
                     util::FormatNumber(time_s.back()) + " s, so the sampling interval " +
                     util::FormatNumber(dt) + " s is not a finite positive number; check the time column.");
  for (std::size_t k = 1; k < time_s.size(); ++k) {
    const double step = time_s[k] - time_s[k - 1];
    if (std::abs(step - dt) > kMaxRelativeJitter * dt)
      throw InputError(source + ": " + sample_name(k) + ": the time step " + util::FormatNumber(step, 9) +
                       " s differs from the mean step " + util::FormatNumber(dt, 9) +
                       " s by more than 1e-6 (relative); samples must be uniformly spaced.");
  }
  return {time_s.front(), dt};
}

CsvSignals ReadSignalsCsv(const std::filesystem::path& path, const engine::ArrayGeometry* array,
                          const CsvColumnMap& column_map) {
  const std::string file = util::EscapeControl(path.string());
  std::string text = ReadWholeFile(path);
  if (text.size() >= 3 && text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);

  CsvSignals result;
  std::vector<std::string> header;
  std::vector<int> wanted_field;  // field index of each output column
  int time_field = -1;
  std::vector<std::vector<double>> columns;
  std::vector<double> time;
  std::vector<long> row_lines;  // file line number of each data row
  std::vector<std::string_view> fields;

  std::size_t position = 0;
  long line_number = 0;
  while (position < text.size()) {
    std::size_t end = text.find('\n', position);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + position, end - position);
    position = end + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.size() > kMaxLineBytes)
      throw InputError(file + ": line " + std::to_string(line_number) + " is " + std::to_string(line.size()) +
                       " bytes long, more than the 1 MiB napkin accepts for one line (header or row).");
    const std::string_view trimmed = util::Trim(line);
    if (trimmed.empty() || trimmed.front() == '#') continue;
    SplitFields(line, fields);

    if (header.empty()) {
      std::map<std::string, int> index_of;
      for (std::size_t i = 0; i < fields.size(); ++i) {
        std::string name(Unquote(fields[i]));
        if (name.empty())
          throw InputError(file + ": header line " + std::to_string(line_number) + ", column " +
                           std::to_string(i + 1) + " has no name.");
        if (!index_of.emplace(name, static_cast<int>(i)).second)
          throw InputError(file + ": header line " + std::to_string(line_number) + " names column " +
                           util::Quoted(name) + " twice.");
        header.push_back(std::move(name));
      }
      const auto time_it = index_of.find(ColumnOf("time_s", column_map));
      if (time_it == index_of.end())
        throw InputError(
            file + ": the header (line " + std::to_string(line_number) + ") has " +
            (ColumnOf("time_s", column_map) == "time_s"
                 ? std::string("no time_s column.")
                 : "no column " + util::Quoted(ColumnOf("time_s", column_map)) + " (mapped to time_s)."));
      time_field = time_it->second;
      if (array != nullptr) {
        for (const auto& [slot, column] : column_map)
          if (slot != "time_s" && !array->FindSlot(slot))
            throw InputError(file + ": the column map names slot " + util::Quoted(slot) + " (column " +
                             util::Quoted(column) + "), which array " + util::Quoted(array->name) +
                             " does not have.");
        for (const engine::Sensor& sensor : array->sensors) {
          const auto it = index_of.find(ColumnOf(sensor.slot, column_map));
          if (it == index_of.end())
            throw InputError(file + ": " + ColumnDescription(sensor.slot, column_map) + " of array " +
                             util::Quoted(array->name) + ".");
          wanted_field.push_back(it->second);
          result.signals.slots.push_back(sensor.slot);
        }
        // One warning for all ignored columns, naming the first few (a file
        // with a million extra columns must not print a million lines).
        std::vector<std::string_view> ignored;
        for (std::size_t i = 0; i < header.size(); ++i)
          if (static_cast<int>(i) != time_field &&
              std::find(wanted_field.begin(), wanted_field.end(), static_cast<int>(i)) == wanted_field.end())
            ignored.push_back(header[i]);
        if (ignored.size() == 1) {
          result.warnings.push_back(file + ": column " + util::Quoted(ignored.front()) +
                                    " is not a slot of array " + util::Quoted(array->name) +
                                    " and is ignored.");
        } else if (!ignored.empty()) {
          result.warnings.push_back(file + ": " + std::to_string(ignored.size()) + " columns (" +
                                    IgnoredColumnNames(ignored) + ") are not slots of array " +
                                    util::Quoted(array->name) + " and are ignored.");
        }
      } else {
        for (std::size_t i = 0; i < header.size(); ++i) {
          if (static_cast<int>(i) == time_field) continue;
          wanted_field.push_back(static_cast<int>(i));
          result.signals.slots.push_back(header[i]);
        }
      }
      columns.resize(wanted_field.size());
      continue;
    }

    if (fields.size() != header.size())
      throw InputError(file + ": row " + std::to_string(line_number) + " has " +
                       std::to_string(fields.size()) + " values but the header has " +
                       std::to_string(header.size()) + " columns.");
    auto parse = [&](int field) {
      const std::string_view value = util::Trim(fields[field]);
      const std::string& column = header[field];
      if (value.empty())
        throw InputError(file + ": row " + std::to_string(line_number) + ", column " + util::Quoted(column) +
                         " is empty.");
      const std::optional<double> number = util::ParseDouble(value);
      if (!number)
        throw InputError(file + ": row " + std::to_string(line_number) + ", column " + util::Quoted(column) +
                         ": " + util::Quoted(value) + " is not a number.");
      if (!std::isfinite(*number))
        RefuseNonFiniteSample(
            file + ": row " + std::to_string(line_number) + ", column " + util::Quoted(column), value);
      return *number;
    };
    time.push_back(parse(time_field));
    for (std::size_t c = 0; c < wanted_field.size(); ++c) columns[c].push_back(parse(wanted_field[c]));
    row_lines.push_back(line_number);
  }

  if (header.empty()) throw InputError(file + ": no header line (expected time_s and one column per slot).");
  CheckSampleCount(time.size(), file, "data row");

  const TimeBase time_base = UniformTimeBase(
      time, file, [&](std::size_t k) { return "row " + std::to_string(row_lines[k]); }, "row");
  engine::TestSignals& signals = result.signals;
  signals.t0_s = time_base.t0_s;
  signals.dt_s = time_base.dt_s;
  signals.file_rows.assign(row_lines.begin(), row_lines.end());
  signals.samples.resize(static_cast<Eigen::Index>(time.size()), static_cast<Eigen::Index>(columns.size()));
  for (std::size_t c = 0; c < columns.size(); ++c)
    signals.samples.col(static_cast<Eigen::Index>(c)) =
        Eigen::Map<const Eigen::VectorXd>(columns[c].data(), static_cast<Eigen::Index>(columns[c].size()));
  return result;
}

void WriteSignalsCsv(const engine::TestSignals& signals, const std::filesystem::path& path,
                     std::span<const std::string> comments) {
  if (static_cast<Eigen::Index>(signals.slots.size()) != signals.samples.cols())
    throw InputError(path.string() + ": cannot write signals whose slot names do not match their columns.");
  util::WriteFileAtomically(path, [&](util::AtomicFile& file) {
    for (const std::string& comment : comments) {
      if (comment.find_first_of("\r\n") != std::string::npos)
        throw InputError(path.string() + ": a comment line holds a line break.");
      file.Write("# " + comment + "\n");
    }
    std::string line = "time_s";
    for (const std::string& slot : signals.slots) line += "," + slot;
    line += '\n';
    file.Write(line);
    for (Eigen::Index k = 0; k < signals.size(); ++k) {
      line.clear();
      util::AppendNumber(line, signals.TimeAt(k));
      for (Eigen::Index c = 0; c < signals.samples.cols(); ++c) {
        line += ',';
        util::AppendNumber(line, signals.samples(k, c));
      }
      line += '\n';
      file.Write(line);
    }
  });
}

const std::vector<std::string>& DerivedCsvColumns() {
  static const std::vector<std::string> kColumns = {"time_s",
                                                    "omega_body_x_radps",
                                                    "omega_body_y_radps",
                                                    "omega_body_z_radps",
                                                    "alpha_body_x_radps2",
                                                    "alpha_body_y_radps2",
                                                    "alpha_body_z_radps2",
                                                    "omega_fixed_x_radps",
                                                    "omega_fixed_y_radps",
                                                    "omega_fixed_z_radps",
                                                    "alpha_fixed_x_radps2",
                                                    "alpha_fixed_y_radps2",
                                                    "alpha_fixed_z_radps2",
                                                    "acc_body_x_g",
                                                    "acc_body_y_g",
                                                    "acc_body_z_g",
                                                    "acc_fixed_x_g",
                                                    "acc_fixed_y_g",
                                                    "acc_fixed_z_g",
                                                    "vel_fixed_x_mps",
                                                    "vel_fixed_y_mps",
                                                    "vel_fixed_z_mps",
                                                    "pos_fixed_x_m",
                                                    "pos_fixed_y_m",
                                                    "pos_fixed_z_m",
                                                    "quat_w",
                                                    "quat_x",
                                                    "quat_y",
                                                    "quat_z",
                                                    "roll_deg",
                                                    "pitch_deg",
                                                    "yaw_deg",
                                                    "dcos_xx_deg",
                                                    "dcos_yy_deg",
                                                    "dcos_zz_deg"};
  return kColumns;
}

std::vector<DerivedChannelSource> DerivedChannelSources(const engine::Kinematics& kinematics) {
  const std::vector<std::string>& names = DerivedCsvColumns();
  std::vector<DerivedChannelSource> sources;
  sources.reserve(names.size());
  auto add = [&](const double* values, Eigen::Index size, double to_csv_unit) {
    sources.push_back({names[sources.size()], {values, static_cast<std::size_t>(size)}, to_csv_unit});
  };
  auto add_columns = [&](const auto& series, double to_csv_unit) {
    static_assert(!std::decay_t<decltype(series)>::IsRowMajor, "a column's values are contiguous");
    for (Eigen::Index c = 0; c < series.cols(); ++c) add(series.col(c).data(), series.rows(), to_csv_unit);
  };
  auto add_absent = [&](std::size_t count) {
    for (std::size_t i = 0; i < count; ++i) add(nullptr, 0, 1.0);
  };
  const double g_per_si = 1.0 / engine::kStandardGravity;
  add(kinematics.time_s.data(), kinematics.time_s.size(), 1.0);
  // An acceleration-only test has no rotation-dependent series (empty, or NaN
  // as stored before; engine::HasRotation).
  if (!engine::HasRotation(kinematics)) {
    add_absent(std::size_t{4} * 3);  // omega_body to alpha_fixed
    add_columns(kinematics.acc_body, g_per_si);
    add_absent(names.size() - sources.size());  // acc_fixed to dcos
    return sources;
  }
  add_columns(kinematics.omega_body, 1.0);
  add_columns(kinematics.alpha_body, 1.0);
  add_columns(kinematics.omega_fixed, 1.0);
  add_columns(kinematics.alpha_fixed, 1.0);
  add_columns(kinematics.acc_body, g_per_si);
  add_columns(kinematics.acc_fixed, g_per_si);
  add_columns(kinematics.vel_fixed, 1.0);
  add_columns(kinematics.pos_fixed, 1.0);
  add_columns(kinematics.quat_fixed_from_body, 1.0);
  add_columns(kinematics.roll_pitch_yaw_rad, engine::kDegPerRad);
  add_columns(kinematics.dcos_rad, engine::kDegPerRad);
  return sources;
}

std::vector<DerivedChannel> DerivedChannels(const engine::Kinematics& kinematics) {
  const std::vector<DerivedChannelSource> sources = DerivedChannelSources(kinematics);
  std::vector<DerivedChannel> channels;
  channels.reserve(sources.size());
  for (const DerivedChannelSource& source : sources) {
    const Eigen::Map<const Eigen::VectorXd> values_si(source.values_si.data(),
                                                      static_cast<Eigen::Index>(source.values_si.size()));
    channels.push_back({std::string(source.name), values_si * source.to_csv_unit});
  }
  return channels;
}

namespace {

// The derived-channel CSV line by line into `write` (the file, or the text of DerivedCsvText).
void WriteDerivedCsvLines(const engine::Kinematics& kinematics,
                          const std::function<void(const std::string&)>& write) {
  // At least 9 significant digits are required (docs/formats.md); 12 keep the
  // file readable and well inside the precision of the solution.
  constexpr int kDigits = 12;
  const std::vector<DerivedChannel> channels = DerivedChannels(kinematics);
  std::string line;
  for (const DerivedChannel& channel : channels) {
    if (!line.empty()) line += ',';
    line += channel.name;
  }
  line += '\n';
  write(line);
  // A channel the test does not have, and a non-finite value, leave the
  // cell empty (docs/formats.md "Derived channels").
  for (Eigen::Index k = 0; k < kinematics.size(); ++k) {
    line.clear();
    for (std::size_t c = 0; c < channels.size(); ++c) {
      if (c > 0) line += ',';
      const Eigen::VectorXd& values = channels[c].values;
      if (values.size() > 0 && std::isfinite(values[k])) util::AppendNumber(line, values[k], kDigits);
    }
    line += '\n';
    write(line);
  }
}

}  // namespace

void WriteDerivedCsv(const engine::Kinematics& kinematics, util::AtomicFile& file) {
  WriteDerivedCsvLines(kinematics, [&](const std::string& line) { file.Write(line); });
}

std::string DerivedCsvText(const engine::Kinematics& kinematics) {
  std::string text;
  WriteDerivedCsvLines(kinematics, [&](const std::string& line) { text += line; });
  return text;
}

void WriteDerivedCsv(const engine::Kinematics& kinematics, const std::filesystem::path& path) {
  util::WriteFileAtomically(path, [&](util::AtomicFile& file) { WriteDerivedCsv(kinematics, file); });
}

}  // namespace napkin::formats
