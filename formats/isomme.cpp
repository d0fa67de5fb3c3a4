#include "formats/isomme.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>

#include "common/error.h"
#include "engine/cfc_filter.h"
#include "engine/units.h"
#include "formats/json_file.h"
#include "util/atomic_file.h"
#include "util/text.h"

namespace napkin::formats {
namespace {

// Input quoted in a message: control characters escaped, a huge value cut (util/text.h).
// Lines of a text file (LF or CRLF), with their 1-based numbers; blank lines skipped.
struct Line {
  long number;
  std::string_view text;
};
std::vector<Line> SplitLines(const std::string& text) {
  std::vector<Line> lines;
  std::size_t position = 0;
  long number = 0;
  while (position < text.size()) {
    std::size_t end = text.find('\n', position);
    if (end == std::string::npos) end = text.size();
    ++number;
    const std::string_view line = util::Trim(std::string_view(text).substr(position, end - position));
    if (!line.empty()) lines.push_back({number, line});
    position = end + 1;
  }
  return lines;
}

using Header = std::vector<std::pair<std::string, std::string>>;

// Parses "key<blanks>:value" lines up to the first line without ':' (the
// first sample of a channel file). Returns the index of that line.
std::size_t ParseHeader(const std::vector<Line>& lines, Header& header) {
  std::size_t i = 0;
  for (; i < lines.size(); ++i) {
    const std::size_t colon = lines[i].text.find(':');
    if (colon == std::string_view::npos) break;
    header.emplace_back(std::string(util::Trim(lines[i].text.substr(0, colon))),
                        std::string(util::Trim(lines[i].text.substr(colon + 1))));
  }
  return i;
}

std::optional<std::string> Lookup(const Header& header, std::string_view key) {
  for (const auto& [k, v] : header)
    if (util::EqualsIgnoreCase(k, key)) return v;
  return std::nullopt;
}

bool IsNoValue(std::string_view value) { return util::EqualsIgnoreCase(util::Trim(value), "NOVALUE"); }

// The entry of `directory` whose name equals `name` ignoring case.
std::optional<std::filesystem::path> FindIgnoringCase(const std::filesystem::path& directory,
                                                      const std::string& name) {
  const std::filesystem::path exact = directory / name;
  std::error_code error;
  if (std::filesystem::exists(exact, error)) return exact;
  for (const auto& entry : std::filesystem::directory_iterator(directory, error))
    if (util::EqualsIgnoreCase(entry.path().filename().string(), name)) return entry.path();
  return std::nullopt;
}

std::string ReadText(const std::filesystem::path& path) { return util::ToUtf8(ReadWholeFile(path)); }

RawChannel ReadChannelFile(const std::filesystem::path& path, const std::string& fallback_code) {
  const std::string file = path.string();
  const std::string text = ReadText(path);
  const std::vector<Line> lines = SplitLines(text);
  Header header;
  const std::size_t first_sample = ParseHeader(lines, header);

  RawChannel channel;
  channel.source = file;
  auto require = [&](std::string_view key) {
    const std::optional<std::string> value = Lookup(header, key);
    if (!value || value->empty() || IsNoValue(*value))
      throw InputError(file + ": the header has no " + util::QuotedLong(key) + ".");
    return *value;
  };
  auto require_number = [&](std::string_view key) {
    const std::string value = require(key);
    const std::optional<double> number = util::ParseDouble(value);
    if (!number || !std::isfinite(*number))
      throw InputError(file + ": " + util::QuotedLong(key) + " is " + util::QuotedLong(value) +
                       ", not a number.");
    return *number;
  };
  const std::optional<std::string> code = Lookup(header, "Channel code");
  channel.code = code && !code->empty() && !IsNoValue(*code) ? *code : fallback_code;
  if (channel.code.empty()) throw InputError(file + ": the header has no \"Channel code\".");
  // ISO/TS 13499 codes begin with the test object and the position (docs/formats.md).
  if (util::Trim(channel.code).size() == 16)
    channel.position = std::string(util::Trim(channel.code).substr(0, 2));
  if (const auto name = Lookup(header, "Name of the channel")) channel.name = *name;
  if (const auto unit = Lookup(header, "Unit")) channel.unit = *unit;
  // Already filtered? The header's class, else the code's filter letter (ISO/TS 13499).
  if (const auto frequency_class = Lookup(header, "Channel frequency class")) {
    const std::optional<double> number = util::ParseDouble(*frequency_class);
    if (number && std::isfinite(*number) && *number > 0.0) channel.prefiltered_cfc = *number;
  }
  if (!channel.prefiltered_cfc && channel.code.size() == 16)
    channel.prefiltered_cfc = IsoMmeFilterClassOfLetter(channel.code[15]);
  channel.dt_s = require_number("Sampling interval");
  if (!(channel.dt_s > 0.0))
    throw InputError(file + ": the sampling interval " + util::FormatNumber(channel.dt_s) +
                     " is not a finite positive number.");
  channel.t0_s = require_number("Time of first sample");
  const std::string declared_text = require("Number of samples");
  const std::optional<long long> declared = util::ParseInteger(declared_text);
  if (!declared || *declared < 0)
    throw InputError(file + ": \"Number of samples\" is " + util::QuotedLong(declared_text) +
                     ", not a count.");

  // Every declared size is checked against the bytes present before anything is allocated (one
  // sample per line after the header, docs/formats.md "ISO-MME (ISO/TS 13499) input").
  const std::size_t sample_lines = lines.size() - first_sample;
  if (static_cast<unsigned long long>(*declared) > sample_lines)
    throw InputError(file + ": channel " + channel.code + ": the header declares " +
                     std::to_string(*declared) + " samples but the file holds " +
                     std::to_string(sample_lines) + " lines of samples.");
  channel.values.reserve(static_cast<std::size_t>(*declared));
  for (std::size_t i = first_sample; i < lines.size(); ++i) {
    const Line& line = lines[i];
    const std::size_t sample = i - first_sample + 1;
    if (IsNoValue(line.text))
      throw InputError(file + ": sample " + std::to_string(sample) + " (line " + std::to_string(line.number) +
                       ") is NOVALUE.");
    const std::optional<double> value = util::ParseDouble(line.text);
    if (!value || !std::isfinite(*value))
      throw InputError(file + ": sample " + std::to_string(sample) + " (line " + std::to_string(line.number) +
                       ") is " + util::QuotedLong(line.text.substr(0, 40)) + ", not a finite number.");
    channel.values.push_back(*value);
  }
  if (static_cast<long long>(channel.values.size()) != *declared)
    throw InputError(file + ": the header declares " + std::to_string(*declared) +
                     " samples but the file holds " + std::to_string(channel.values.size()) + ".");
  return channel;
}

// Header line: key padded to 28 characters, ':', value (ISO/TS 13499 layout).
void AppendHeaderLine(std::string& out, std::string_view key, std::string_view value) {
  out += key;
  if (key.size() < 28) out.append(28 - key.size(), ' ');
  out += ':';
  out += value;
  out += '\n';
}

std::string ChannelFileName(const std::string& test_number, std::size_t index) {
  char suffix[48];
  std::snprintf(suffix, sizeof(suffix), ".%03zu", index);
  return test_number + suffix;
}

struct OutputChannel {
  std::string code;
  std::string name;
  std::string unit;
  std::string reference_system;  // "local" (body axes) or "global" (fixed axes)
  std::optional<double> cfc;     // filter class applied (nullopt: none)
  std::vector<double> values;
};

// The shortest decimal without exponent that reads back as `value` (0.0001, not 1e-04).
std::string FixedDecimal(double value) {
  char buffer[400];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value, std::chars_format::fixed);
  return std::string(buffer, result.ptr);
}

// The decimal a computed grid value stands for: 15 significant digits
// ((t_last - t_first) / (n - 1) = 9.9999999999999991e-05 is 0.0001).
double IntendedDecimal(double value) { return *util::ParseDouble(util::FormatNumber(value, 15)); }

void WriteTestFolder(const std::filesystem::path& folder, const std::string& test_number, double dt,
                     double t0, const std::vector<OutputChannel>& channels, int precision) {
  // No separator, control character (a newline), ".", ".." or hidden name
  // may reach a file name (docs/formats.md "Names, limits and escaping").
  if (test_number.empty() || test_number != util::FileNameComponent(test_number))
    throw InputError(folder.string() + ": " + util::QuotedLong(test_number) +
                     " cannot name ISO-MME files (use " +
                     util::QuotedLong(util::FileNameComponent(test_number)) + ").");
  util::WriteDirectoryAtomically(folder, [&](const std::filesystem::path& directory) {
    std::string mme;
    AppendHeaderLine(mme, "Data format", "ISO-MME");
    AppendHeaderLine(mme, "Version", "1.6");
    AppendHeaderLine(mme, "Test number", test_number);
    AppendHeaderLine(mme, "Laboratory name", "napkin");
    AppendHeaderLine(mme, "Number of test objects", "1");
    util::WriteFileAtomically(directory / (test_number + ".mme"),
                              [&](util::AtomicFile& file) { file.Write(mme); });

    const std::filesystem::path channel_dir = directory / "Channel";
    std::filesystem::create_directory(channel_dir);
    std::string chn;
    AppendHeaderLine(chn, "Instrumentation standard", "ISO 6487");
    AppendHeaderLine(chn, "Number of channels", std::to_string(channels.size()));
    for (std::size_t i = 0; i < channels.size(); ++i) {
      char key[64];
      std::snprintf(key, sizeof(key), "Name of channel %03zu", i + 1);
      AppendHeaderLine(chn, key, channels[i].code + " / " + channels[i].name);
    }
    util::WriteFileAtomically(channel_dir / (test_number + ".chn"),
                              [&](util::AtomicFile& file) { file.Write(chn); });

    for (std::size_t i = 0; i < channels.size(); ++i) {
      const OutputChannel& channel = channels[i];
      std::string text;
      AppendHeaderLine(text, "Channel code", channel.code);
      AppendHeaderLine(text, "Name of the channel", channel.name);
      AppendHeaderLine(text, "Data source", "calculated");
      AppendHeaderLine(text, "Reference system", channel.reference_system);
      AppendHeaderLine(text, "Sampling interval", FixedDecimal(dt));
      AppendHeaderLine(text, "Channel frequency class",
                       channel.cfc ? util::FormatNumber(*channel.cfc) : "NOVALUE");
      AppendHeaderLine(text, "Reference channel", "implicit");
      AppendHeaderLine(text, "Unit", channel.unit);
      AppendHeaderLine(text, "Time of first sample", util::FormatNumber(t0));
      AppendHeaderLine(text, "Number of samples", std::to_string(channel.values.size()));
      AppendHeaderLine(text, "Data status", "ok");
      for (const double value : channel.values) {
        util::AppendNumber(text, value, precision);
        text += '\n';
      }
      util::WriteFileAtomically(channel_dir / ChannelFileName(test_number, i + 1),
                                [&](util::AtomicFile& file) { file.Write(text); });
    }
  });
}

std::string IsoUnit(const std::string& unit) {
  if (unit == "m/s^2" || unit == "m/s2" || unit == "m/s**2") return "m/s**2";
  return unit;  // g, rad/s, deg/s
}

}  // namespace

std::optional<double> IsoMmeFilterClassOfLetter(char letter) {
  switch (letter) {
    case 'A':
    case 'a':
      return engine::kCfc1000;
    case 'B':
    case 'b':
      return engine::kCfc600;
    case 'C':
    case 'c':
      return engine::kCfc180;
    case 'D':
    case 'd':
      return engine::kCfc60;
    default:
      return std::nullopt;
  }
}

std::optional<char> IsoMmeFilterLetter(double cfc) {
  for (const char letter : {'A', 'B', 'C', 'D'}) {
    const double standard = *IsoMmeFilterClassOfLetter(letter);
    if (std::abs(cfc - standard) <= 1e-9 * standard) return letter;
  }
  return std::nullopt;
}

char FilterClassLetter(std::optional<double> cfc) {
  if (!cfc) return '0';
  return IsoMmeFilterLetter(*cfc).value_or('X');
}

std::string IsoMmeTest::TestNumber() const {
  for (const auto& [key, value] : test_info)
    if (util::EqualsIgnoreCase(key, "Test number") && !value.empty() && !IsNoValue(value)) return value;
  return name;
}

TestInfo IsoMmeTestInfo(const IsoMmeTest& test, const RawChannel& head_channel) {
  auto value_of = [&](const std::string& key) -> std::string {
    const std::optional<std::string> value = Lookup(test.test_info, key);
    return value && !IsNoValue(*value) ? *value : std::string();
  };
  TestInfo info;
  info.test_number = test.TestNumber();
  info.title = value_of("Title");
  info.date = value_of("Date of the test");
  info.laboratory = value_of("Laboratory name");
  const std::string code(util::Trim(head_channel.code));
  if (code.size() == 16) {
    info.vehicle = value_of(std::string("Name of test object ") + code[0]);
    const std::string fine3 = code.substr(10, 2);
    if (fine3 != "00" && fine3 != "??") info.dummy = fine3;
  }
  return info;
}

IsoMmeTest ReadIsoMme(const std::filesystem::path& folder_or_mme) {
  IsoMmeTest test;
  std::filesystem::path mme;
  std::error_code error;
  if (std::filesystem::is_directory(folder_or_mme, error)) {
    test.folder = folder_or_mme;
    std::vector<std::filesystem::path> candidates;
    for (const auto& entry : std::filesystem::directory_iterator(folder_or_mme, error))
      if (entry.is_regular_file() && util::EqualsIgnoreCase(entry.path().extension().string(), ".mme"))
        candidates.push_back(entry.path());
    if (candidates.size() != 1)
      throw InputError(folder_or_mme.string() +
                       ": an ISO-MME test folder holds one .mme file, this one holds " +
                       std::to_string(candidates.size()) + ".");
    mme = candidates.front();
  } else if (std::filesystem::is_regular_file(folder_or_mme, error)) {
    mme = folder_or_mme;
    test.folder = folder_or_mme.parent_path();
    if (test.folder.empty()) test.folder = ".";
  } else {
    throw InputError(folder_or_mme.string() + ": no such ISO-MME test folder or .mme file.");
  }
  test.name = mme.stem().string();
  {
    const std::string text = ReadText(mme);
    ParseHeader(SplitLines(text), test.test_info);
  }

  const std::optional<std::filesystem::path> channel_dir = FindIgnoringCase(test.folder, "Channel");
  if (!channel_dir || !std::filesystem::is_directory(*channel_dir, error))
    throw InputError(test.folder.string() + ": the ISO-MME test folder has no Channel folder.");
  const std::optional<std::filesystem::path> chn = FindIgnoringCase(*channel_dir, test.name + ".chn");
  if (!chn)
    throw InputError((*channel_dir / (test.name + ".chn")).string() + ": the channel list is missing.");
  const std::string chn_text = ReadText(*chn);
  const std::vector<Line> chn_lines = SplitLines(chn_text);  // views into chn_text
  Header chn_header;
  ParseHeader(chn_lines, chn_header);
  const std::optional<std::string> count_text = Lookup(chn_header, "Number of channels");
  const std::optional<long long> count = count_text ? util::ParseInteger(*count_text) : std::nullopt;
  if (!count || *count < 1)
    throw InputError(chn->string() + ": \"Number of channels\" is missing or not a positive count.");
  for (long long i = 1; i <= *count; ++i) {
    const std::string file_name = ChannelFileName(test.name, static_cast<std::size_t>(i));
    const std::optional<std::filesystem::path> path = FindIgnoringCase(*channel_dir, file_name);
    if (!path)
      throw InputError((*channel_dir / file_name).string() + ": channel " + std::to_string(i) + " of " +
                       std::to_string(*count) + " listed in " + chn->filename().string() + " is missing.");
    // "Name of channel 001 : <code> / <name>" stands in for a missing Channel code.
    char key[64];
    std::snprintf(key, sizeof(key), "Name of channel %03lld", i);
    std::string fallback_code;
    if (const auto listed = Lookup(chn_header, key))
      fallback_code = std::string(util::Trim(listed->substr(0, listed->find('/'))));
    test.channels.push_back(ReadChannelFile(*path, fallback_code));
  }
  return test;
}

engine::TestSignals ReadIsoMmeSignals(const std::filesystem::path& folder_or_mme,
                                      const engine::ArrayGeometry& array, const ChannelMap& map) {
  const IsoMmeTest test = ReadIsoMme(folder_or_mme);
  const std::string test_name = test.TestNumber();
  const std::vector<std::size_t> channel_of_sensor = AssignSlots(test.channels, array, map, test_name);
  // A channel feeding a slot must say its unit: a missing or NOVALUE "Unit"
  // is an error, never silently the slot's unit (docs/formats.md).
  for (std::size_t s = 0; s < channel_of_sensor.size(); ++s) {
    const RawChannel& channel = test.channels[channel_of_sensor[s]];
    if (!ParseSignalUnit(channel.unit, channel.Label()))
      throw InputError(channel.source + ": the header has no \"Unit\" for channel " + channel.code +
                       ", which feeds slot " + util::QuotedLong(array.sensors[s].slot) +
                       "; add the unit (e.g. g, m/s**2, deg/s, rad/s).");
  }
  return AssembleSignals(test.channels, channel_of_sensor, array, test_name);
}

std::string CodeForSlot(const ChannelMap& map, const std::string& slot) {
  const ChannelMapEntry* entry = map.Find(slot);
  if (entry == nullptr || entry->codes.empty())
    throw InputError(map.source + ": channel map " + util::QuotedLong(map.name) +
                     " has no code pattern for slot " + util::QuotedLong(slot) + ".");
  std::string code = entry->codes.front();
  for (std::size_t i = 0; i < code.size(); ++i)
    if (code[i] == '?') code[i] = i < 2 ? '1' : '0';
  return code;
}

void WriteIsoMme(const engine::TestSignals& signals, const engine::ArrayGeometry& array,
                 const ChannelMap& map, const std::filesystem::path& folder, const std::string& test_number) {
  std::vector<OutputChannel> channels;
  std::map<std::string, std::string> slot_of_code;
  for (Eigen::Index c = 0; c < signals.samples.cols(); ++c) {
    const std::string& slot = signals.slots.at(static_cast<std::size_t>(c));
    OutputChannel channel;
    channel.code = CodeForSlot(map, slot);
    if (const auto [it, inserted] = slot_of_code.emplace(channel.code, slot); !inserted)
      throw InputError(map.source + ": slots " + util::QuotedLong(it->second) + " and " +
                       util::QuotedLong(slot) + " would both be written as channel " + channel.code + ".");
    if (const std::optional<double> prefiltered = signals.PrefilteredCfc(c)) {
      if (*prefiltered == engine::kPrefilteredClassUnknown) {
        channel.code[15] = 'X';  // filtered, class not stated: no frequency class (NOVALUE)
      } else {
        channel.cfc = *prefiltered;
        if (const std::optional<char> letter = IsoMmeFilterLetter(*prefiltered)) channel.code[15] = *letter;
      }
    }
    channel.name = "Head " + slot;
    channel.unit = "g";
    for (const engine::Sensor& sensor : array.sensors)
      if (sensor.slot == slot) channel.unit = IsoUnit(sensor.unit);
    channel.reference_system = "local";
    channel.values.assign(signals.samples.col(c).data(), signals.samples.col(c).data() + signals.size());
    channels.push_back(std::move(channel));
  }
  WriteTestFolder(folder, test_number, signals.dt_s, signals.t0_s, channels, 0);
}

void WriteDerivedIsoMme(const engine::Kinematics& kinematics, const std::filesystem::path& folder,
                        const std::string& test_number, const IsoMmeExportOptions& options) {
  const Eigen::Index n = kinematics.size();
  if (n < 2) throw InputError(folder.string() + ": cannot export fewer than two samples.");
  auto code_field = [&](const std::string& value, const char* what) {
    if (value.size() != 2 || !std::all_of(value.begin(), value.end(), [](char c) {
          return (c >= '0' && c <= '9') || (c >= 'A' && c <= 'Z');
        }))
      throw UsageError("the ISO-MME " + std::string(what) + " \"" + value +
                       "\" is not two characters 0-9 or A-Z.");
  };
  code_field(options.position, "position");
  code_field(options.dummy_type, "dummy type");
  const double dt =
      IntendedDecimal((kinematics.time_s[n - 1] - kinematics.time_s[0]) / static_cast<double>(n - 1));
  // Linear motion comes from the accelerometers; angular motion from the
  // rate sensors when the array has them, else from the accelerometers.
  const std::optional<double> linear_cfc = options.linear_cfc;
  const std::optional<double> angular_cfc =
      options.angular_rate_sensors ? options.angular_rate_cfc : options.linear_cfc;
  // ISO/TS 13499 code: position (2), HEAD, fine locations 1-2, dummy type
  // (fine location 3), dimension, direction, filter class.
  auto code = [&](const char* fine12, const char* dimension, char direction, std::optional<double> cfc) {
    return options.position + "HEAD" + fine12 + options.dummy_type + dimension + direction +
           FilterClassLetter(cfc);
  };
  std::vector<OutputChannel> channels;
  const char axes[3] = {'X', 'Y', 'Z'};
  // Fine locations 1-2: "0000" body axes (the head CG sensor's own code),
  // "00GL" fixed (global) axes, "00DC" direction-cosine angles.
  auto add3 = [&](const engine::Series3& series, const char* fine12, const char* dimension, const char* unit,
                  const char* what, double scale, std::optional<double> cfc) {
    for (int a = 0; a < 3; ++a) {
      OutputChannel channel;
      channel.code = code(fine12, dimension, axes[a], cfc);
      channel.name = std::string("Head CG ") + what + " " + axes[a];
      channel.unit = unit;
      channel.reference_system = std::string(fine12) == "0000" ? "local" : "global";
      channel.cfc = cfc;
      channel.values.resize(static_cast<std::size_t>(n));
      for (Eigen::Index k = 0; k < n; ++k) channel.values[static_cast<std::size_t>(k)] = series(k, a) * scale;
      channels.push_back(std::move(channel));
    }
  };
  const double g_per_si = 1.0 / engine::kStandardGravity;
  add3(kinematics.acc_body, "0000", "AC", "g", "acceleration, body axes", g_per_si, linear_cfc);
  if (!engine::HasRotation(kinematics)) {
    // Acceleration only (docs/formats.md "ISO-MME export"): the CG acceleration
    // and its resultant (direction R); everything else needs the rotation.
    OutputChannel resultant;
    resultant.code = code("0000", "AC", 'R', linear_cfc);
    resultant.name = "Head CG acceleration, resultant";
    resultant.unit = "g";
    resultant.reference_system = "local";
    resultant.cfc = linear_cfc;
    resultant.values.resize(static_cast<std::size_t>(n));
    for (Eigen::Index k = 0; k < n; ++k)
      resultant.values[static_cast<std::size_t>(k)] = kinematics.acc_body.row(k).norm() * g_per_si;
    channels.push_back(std::move(resultant));
    WriteTestFolder(folder, test_number, dt, IntendedDecimal(kinematics.time_s[0]), channels, 0);
    return;
  }
  add3(kinematics.acc_fixed, "00GL", "AC", "g", "acceleration, fixed axes", g_per_si, linear_cfc);
  add3(kinematics.vel_fixed, "00GL", "VE", "m/s", "velocity, fixed axes", 1.0, linear_cfc);
  add3(kinematics.pos_fixed, "00GL", "DS", "m", "displacement, fixed axes", 1.0, linear_cfc);
  add3(kinematics.omega_body, "0000", "AV", "rad/s", "angular velocity, body axes", 1.0, angular_cfc);
  add3(kinematics.omega_fixed, "00GL", "AV", "rad/s", "angular velocity, fixed axes", 1.0, angular_cfc);
  add3(kinematics.alpha_body, "0000", "AA", "rad/s**2", "angular acceleration, body axes", 1.0, angular_cfc);
  add3(kinematics.alpha_fixed, "00GL", "AA", "rad/s**2", "angular acceleration, fixed axes", 1.0,
       angular_cfc);
  add3(kinematics.roll_pitch_yaw_rad, "00GL", "AN", "deg", "roll/pitch/yaw angle about fixed",
       engine::kDegPerRad, angular_cfc);
  add3(kinematics.dcos_rad, "00DC", "AN", "deg", "angle between body and fixed axis", engine::kDegPerRad,
       angular_cfc);
  const char quaternion_parts[4] = {'W', 'X', 'Y', 'Z'};
  for (int c = 0; c < 4; ++c) {
    OutputChannel channel;
    channel.code = code("00GL", "QU", quaternion_parts[c], angular_cfc);
    channel.name = std::string("Head orientation quaternion (body to fixed) ") + quaternion_parts[c];
    channel.unit = "1";
    channel.reference_system = "global";
    channel.cfc = angular_cfc;
    channel.values.assign(kinematics.quat_fixed_from_body.col(c).data(),
                          kinematics.quat_fixed_from_body.col(c).data() + n);
    channels.push_back(std::move(channel));
  }
  // Shortest exact numbers: a re-import reads back the very doubles napkin computed.
  WriteTestFolder(folder, test_number, dt, IntendedDecimal(kinematics.time_s[0]), channels, 0);
}

}  // namespace napkin::formats
