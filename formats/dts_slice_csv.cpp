#include "formats/dts_slice_csv.h"

#include <cmath>
#include <map>
#include <optional>

#include "common/error.h"
#include "formats/csv.h"
#include "formats/json_file.h"
#include "util/text.h"

namespace napkin::formats {
namespace {

// The longest row napkin reads (docs/formats.md "Names, limits and escaping", as for napkin's CSV).
constexpr std::size_t kMaxRowBytes = std::size_t{1} << 20;
// A time may stray from the sample rate's grid by a tenth of the sampling interval: the export
// rounds the times it writes, never by that much (docs/formats.md "DTS SLICEWare CSV").
constexpr double kTimeTolerance = 0.1;

// One row of the export: its file line and its cells, trimmed and unquoted.
struct Row {
  long line = 0;
  std::vector<std::string> cells;
};

// Splits a row at commas outside double quotes ("" inside quotes is one quote).
std::vector<std::string> SplitCells(std::string_view text) {
  std::vector<std::string> cells(1);
  bool quoted = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '"') {
      if (quoted && i + 1 < text.size() && text[i + 1] == '"') {
        cells.back() += '"';
        ++i;
      } else {
        quoted = !quoted;
      }
    } else if (c == ',' && !quoted) {
      cells.emplace_back();
    } else {
      cells.back() += c;
    }
  }
  for (std::string& cell : cells) cell = std::string(util::Trim(cell));
  return cells;
}

// The rows of `text` (LF or CRLF), blank rows skipped.
class RowReader {
 public:
  RowReader(const std::string& text, std::string file) : text_(text), file_(std::move(file)) {}

  std::optional<Row> Next() {
    while (position_ < text_.size()) {
      std::size_t end = text_.find('\n', position_);
      if (end == std::string::npos) end = text_.size();
      std::string_view line(text_.data() + position_, end - position_);
      position_ = end + 1;
      ++line_;
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      if (line.size() > kMaxRowBytes)
        throw InputError(file_ + ": row " + std::to_string(line_) + " is " + std::to_string(line.size()) +
                         " bytes long, more than the 1 MiB napkin accepts for one row.");
      if (util::Trim(line).empty()) continue;
      return Row{line_, SplitCells(line)};
    }
    return std::nullopt;
  }

 private:
  const std::string& text_;
  std::string file_;
  std::size_t position_ = 0;
  long line_ = 0;
};

// The rows before `Data Starts Here`, by name (case-insensitive).
class InformationRows {
 public:
  void Add(Row row) {
    const std::string key = util::ToLower(row.cells.front());
    rows_.try_emplace(key, std::move(row));
  }
  const Row* Find(std::string_view name) const {
    const auto found = rows_.find(util::ToLower(name));
    return found == rows_.end() ? nullptr : &found->second;
  }

 private:
  std::map<std::string, Row> rows_;
};

bool IsBlankValue(std::string_view value) {
  return value.empty() || util::EqualsIgnoreCase(value, "none") || util::EqualsIgnoreCase(value, "novalue") ||
         util::EqualsIgnoreCase(value, "n/a") || util::EqualsIgnoreCase(value, "unfiltered");
}

// ISO/TS 13499 code parts (formats/isomme.h): main location, physical dimension, direction.
bool IsHeadKinematicCode(std::string_view code) {
  return code.size() == 16 && util::EqualsIgnoreCase(code.substr(2, 4), "HEAD") &&
         (util::EqualsIgnoreCase(code.substr(12, 2), "AC") ||
          util::EqualsIgnoreCase(code.substr(12, 2), "AV"));
}
bool IsBodyAxisLetter(char direction) {
  return direction == 'X' || direction == 'Y' || direction == 'Z' || direction == 'x' || direction == 'y' ||
         direction == 'z';
}

class ExportReader {
 public:
  explicit ExportReader(const std::filesystem::path& path)
      : file_(util::EscapeControl(path.string())),
        // Windows' SLICEWare writes ANSI text: what is not UTF-8 is read as ISO-8859-1.
        text_(util::ToUtf8(ReadWholeFile(path))),
        rows_(text_, file_) {
    result_.file = path;
  }

  DtsSliceExport Read() {
    ReadInformationRows();
    ReadColumnRow();
    ReadChannelRows();
    ReadSamples();
    return std::move(result_);
  }

 private:
  std::string RowNamed(const Row& row) const {
    return file_ + ": row " + std::to_string(row.line) + " (" + util::Quoted(row.cells.front()) + ")";
  }
  std::string Channel(std::size_t c) const {
    std::string named = "channel " + util::Quoted(columns_.at(c));
    if (c < result_.channels.size() && !result_.channels[c].code.empty())
      named += " (" + result_.channels[c].code + ")";
    return named;
  }

  void ReadInformationRows() {
    for (;;) {
      std::optional<Row> row = rows_.Next();
      if (!row)
        throw InputError(file_ +
                         ": no row \"Data Starts Here\"; a SLICEWare CSV export has one between its channel "
                         "information and its samples.");
      if (util::EqualsIgnoreCase(row->cells.front(), "Data Starts Here")) return;
      information_.Add(std::move(*row));
    }
  }

  // `Time,Chan 0:<serial>,...`: the channels are its columns after the time.
  void ReadColumnRow() {
    std::optional<Row> row = rows_.Next();
    if (!row || !util::ToLower(row->cells.front()).starts_with("time"))
      throw InputError(file_ + ": row " + (row ? std::to_string(row->line) : std::string("after the last")) +
                       " should be the column row \"Time,Chan 0:...\" that follows \"Data Starts Here\".");
    columns_.assign(row->cells.begin() + 1, row->cells.end());
    while (!columns_.empty() && columns_.back().empty()) columns_.pop_back();  // trailing commas
    if (columns_.empty())
      throw InputError(file_ + ": row " + std::to_string(row->line) +
                       " (the column row) names no channel after the time column.");
    for (std::size_t c = 0; c < columns_.size(); ++c)
      if (columns_[c].empty())
        throw InputError(file_ + ": row " + std::to_string(row->line) + " (the column row): column " +
                         std::to_string(c + 2) + " has no name.");
    result_.channels.resize(columns_.size());
  }

  // The values of row `name` for every channel; nullptr when the export has no such row. A row
  // with fewer values than channels is refused naming the first channel without one.
  const Row* ChannelValues(std::string_view name, bool required) const {
    const Row* row = information_.Find(name);
    if (row == nullptr) {
      if (!required) return nullptr;
      throw InputError(file_ + ": no row " + util::Quoted(name) +
                       " before \"Data Starts Here\"; napkin needs it for every channel.");
    }
    if (row->cells.size() - 1 < columns_.size())
      throw InputError(RowNamed(*row) + " has " + std::to_string(row->cells.size() - 1) + " values for " +
                       std::to_string(columns_.size()) + " channels: " + Channel(row->cells.size() - 1) +
                       " has none.");
    return row;
  }

  std::string TestValue(std::string_view name) const {
    const Row* row = information_.Find(name);
    return row == nullptr || row->cells.size() < 2 ? std::string() : row->cells[1];
  }

  void ReadChannelRows() {
    result_.test_id = TestValue("Test ID");
    result_.info.test_number = result_.test_id;
    result_.info.title = TestValue("Test Description");
    const std::string date = TestValue("Test Date");
    const std::string time = TestValue("Test Time");
    result_.info.date = date.empty() || time.empty() ? date + time : date + " " + time;

    const Row& codes = *ChannelValues("ISO Channel Code", true);
    const Row& units = *ChannelValues("Engineering Unit", true);
    const Row& rates = *ChannelValues("Sample Rate (Hz)", true);
    const Row* filters = ChannelValues("Software Filter (SAE Class)", false);
    const Row* serials = ChannelValues("Sensor S/N", false);
    const Row* hardware_filters = ChannelValues("Hardware AA Filter (-3dB)", false);
    const Row* descriptions = ChannelValues("Channel Description", false);
    for (std::size_t c = 0; c < columns_.size(); ++c) {
      RawChannel& channel = result_.channels[c];
      channel.source =
          file_ + ": column " + util::Quoted(columns_[c]) + ", code in row " + std::to_string(codes.line);
      channel.code = codes.cells[c + 1];
      if (channel.code.size() == 16) channel.position = channel.code.substr(0, 2);
      channel.unit = units.cells[c + 1];
      if (descriptions != nullptr) channel.name = descriptions->cells[c + 1];
      if (serials != nullptr) channel.serial = serials->cells[c + 1];
      if (hardware_filters != nullptr && !IsBlankValue(hardware_filters->cells[c + 1]))
        channel.hardware_filter = hardware_filters->cells[c + 1];
      if (IsHeadKinematicCode(channel.code)) CheckHeadChannel(c, codes, units);
      if (filters != nullptr) channel.prefiltered_cfc = SoftwareFilter(c, *filters);
      const std::string& rate_text = rates.cells[c + 1];
      const std::optional<double> rate = util::ParseDouble(rate_text);
      if (!rate || !std::isfinite(*rate) || *rate <= 0.0)
        throw InputError(RowNamed(rates) + ", " + Channel(c) + ": " + util::Quoted(rate_text) +
                         " is not a sample rate in Hz.");
      if (c > 0 && *rate != rate_hz_)
        throw InputError(RowNamed(rates) + ": " + Channel(c) + " is sampled at " + util::FormatNumber(*rate) +
                         " Hz, " + Channel(0) + " at " + util::FormatNumber(rate_hz_) +
                         " Hz; the export's one time column serves channels of one sample rate.");
      rate_hz_ = *rate;
      rate_row_ = rates.line;
    }
  }

  // A head accelerometer or angular-rate channel: its unit must be one napkin reads and its
  // direction a body axis, or no slot can take it.
  void CheckHeadChannel(std::size_t c, const Row& codes, const Row& units) {
    const RawChannel& channel = result_.channels[c];
    const std::string where_unit = RowNamed(units) + ", " + Channel(c);
    if (!ParseSignalUnit(channel.unit, where_unit))
      throw InputError(where_unit + ": the head channel has no engineering unit (e.g. g, deg/sec).");
    if (!IsBodyAxisLetter(channel.code[14]))
      throw InputError(RowNamed(codes) + ", " + Channel(c) + ": the code's direction " +
                       util::Quoted(channel.code.substr(14, 1)) +
                       " is no body axis (X, Y or Z), so the head channel maps to no slot.");
  }

  // `Software Filter (SAE Class)`: the CFC class SLICEWare filtered the channel at, or none.
  std::optional<double> SoftwareFilter(std::size_t c, const Row& filters) const {
    const std::string& text = filters.cells[c + 1];
    if (IsBlankValue(text) || text == "0") return std::nullopt;
    const std::optional<double> cfc = util::ParseDouble(text);
    if (!cfc || !std::isfinite(*cfc) || *cfc <= 0.0)
      throw InputError(RowNamed(filters) + ", " + Channel(c) + ": " + util::Quoted(text) +
                       " is no SAE filter class (a CFC such as 1000, or None).");
    return *cfc;
  }

  void ReadSamples() {
    std::vector<double> time;
    std::vector<long> lines;
    for (std::optional<Row> row; (row = rows_.Next());) {
      const std::vector<std::string>& cells = row->cells;
      const std::string where = file_ + ": row " + std::to_string(row->line);
      std::size_t values = cells.size() - 1;
      while (values > 0 && cells[values].empty()) --values;  // trailing commas
      if (values > columns_.size())
        throw InputError(where + " has " + std::to_string(values) + " values after the time for " +
                         std::to_string(columns_.size()) + " channels.");
      if (values < columns_.size())
        throw InputError(where + " has " + std::to_string(values) + " values after the time for " +
                         std::to_string(columns_.size()) + " channels: " + Channel(values) + " has none.");
      time.push_back(Number(cells[0], where + ", the time column"));
      for (std::size_t c = 0; c < columns_.size(); ++c)
        result_.channels[c].values.push_back(Number(cells[c + 1], where + ", " + Channel(c)));
      lines.push_back(row->line);
    }
    CheckSampleCount(time.size(), file_, "data row");
    // The time column and the sample rate say the same (docs/formats.md "DTS SLICEWare CSV").
    const double dt = 1.0 / rate_hz_;
    for (std::size_t k = 1; k < time.size(); ++k) {
      const double expected = time.front() + static_cast<double>(k) / rate_hz_;
      if (std::abs(time[k] - expected) > kTimeTolerance * dt)
        throw InputError(
            file_ + ": row " + std::to_string(lines[k]) + ": the time " + util::FormatNumber(time[k], 9) +
            " s disagrees with the sample rate " + util::FormatNumber(rate_hz_) + " Hz (row " +
            std::to_string(rate_row_) + "), by which this row's sample, " + std::to_string(k) +
            (k == 1 ? " sample" : " samples") + " after the first row's (" +
            util::FormatNumber(time.front(), 9) + " s), is at " + util::FormatNumber(expected, 9) + " s.");
    }
    for (RawChannel& channel : result_.channels) {
      channel.dt_s = dt;
      channel.t0_s = time.front();
    }
  }

  static double Number(const std::string& cell, const std::string& where) {
    if (cell.empty()) throw InputError(where + " is empty.");
    const std::optional<double> value = util::ParseDouble(cell);
    if (!value) throw InputError(where + ": " + util::Quoted(cell) + " is not a number.");
    if (!std::isfinite(*value)) RefuseNonFiniteSample(where, cell);
    return *value;
  }

  std::string file_;
  std::string text_;
  RowReader rows_;
  InformationRows information_;
  std::vector<std::string> columns_;  // the column row's channel names
  double rate_hz_ = 0.0;
  long rate_row_ = 0;
  DtsSliceExport result_;
};

}  // namespace

bool LooksLikeDtsSliceCsv(std::string_view first_bytes) {
  if (first_bytes.starts_with("\xEF\xBB\xBF")) first_bytes.remove_prefix(3);
  const std::size_t end = first_bytes.find_first_of(",\r\n");
  std::string_view first_cell = util::Trim(first_bytes.substr(0, end));
  if (first_cell.size() >= 2 && first_cell.front() == '"' && first_cell.back() == '"')
    first_cell = first_cell.substr(1, first_cell.size() - 2);
  return util::EqualsIgnoreCase(first_cell, "Headers");
}

DtsSliceExport ReadDtsSliceCsv(const std::filesystem::path& path) { return ExportReader(path).Read(); }

}  // namespace napkin::formats
