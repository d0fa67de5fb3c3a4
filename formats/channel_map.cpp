#include "formats/channel_map.h"

#include <cmath>
#include <limits>

#include "common/error.h"
#include "engine/units.h"
#include "formats/array_json.h"
#include "formats/json_file.h"
#include "formats/presets.h"
#include "util/text.h"

namespace napkin::formats {
namespace {

// Input quoted in a message: control characters escaped, a huge value cut (util/text.h).
}  // namespace

std::string RawChannel::Label() const {
  if (!code.empty()) return "channel " + code + " (" + source + ")";
  return source;
}

std::optional<SignalUnit> ParseSignalUnit(std::string_view unit, const std::string& where) {
  const std::string_view trimmed = util::Trim(unit);
  if (trimmed.empty() || util::EqualsIgnoreCase(trimmed, "NOVALUE") ||
      util::EqualsIgnoreCase(trimmed, "NONE"))
    return std::nullopt;
  if (const std::optional<SignalUnit> parsed = engine::SignalUnitToSi(trimmed)) return parsed;
  throw InputError(
      where + ": unrecognised unit " + util::QuotedLong(trimmed) +
      " (napkin reads accelerations in g, m/s^2, ft/s^2, in/s^2 and angular rates in rad/s or deg/s).");
}

const ChannelMapEntry* ChannelMap::Find(std::string_view slot) const {
  for (const auto& [name, entry] : slots)
    if (name == slot) return &entry;
  return nullptr;
}

std::vector<std::pair<std::string, std::string>> ChannelMap::CsvColumns() const {
  std::vector<std::pair<std::string, std::string>> columns;
  for (const auto& [name, entry] : slots)
    if (!entry.column.empty()) columns.emplace_back(name, entry.column);
  return columns;
}

ChannelMap ParseChannelMap(const nlohmann::json& json, const std::string& source) {
  auto fail = [&](const std::string& problem) -> void { throw InputError(source + ": " + problem + "."); };
  if (!json.is_object()) fail("a channel map must be a JSON object");
  ChannelMap map;
  map.source = source;
  if (const auto name = json.find("name"); name != json.end()) {
    if (!name->is_string()) fail("\"name\" must be a string");
    map.name = name->get<std::string>();
    try {
      util::CheckName("the channel map's \"name\"", map.name);
    } catch (const InputError& error) {
      std::string problem = error.what();
      problem.pop_back();  // fail adds the full stop
      fail(problem);
    }
  }
  const auto slots = json.find("slots");
  if (slots == json.end()) fail("the channel map has no \"slots\"");
  if (!slots->is_object()) fail("\"slots\" must be an object (slot name -> {code, senatt, axis})");
  for (const auto& [slot, value] : slots->items()) {
    const std::string where = "slot " + util::QuotedLong(slot);
    if (!value.is_object())
      fail(where + " must map to an object with \"code\", \"senatt\", \"axis\" and/or \"column\"");
    ChannelMapEntry entry;
    if (const auto code = value.find("code"); code != value.end()) {
      if (code->is_string()) {
        entry.codes.push_back(code->get<std::string>());
      } else if (code->is_array()) {
        for (const auto& alternative : *code) {
          if (!alternative.is_string()) fail(where + ": \"code\" alternatives must be strings");
          entry.codes.push_back(alternative.get<std::string>());
        }
      } else {
        fail(where + ": \"code\" must be a string or an array of strings");
      }
      for (const std::string& pattern : entry.codes)
        if (pattern.size() != 16)
          fail(where + ": code pattern " + util::QuotedLong(pattern) + " has " +
               std::to_string(pattern.size()) + " characters, ISO/TS 13499 channel codes have 16");
    }
    for (const auto& [key, field] : {std::pair<const char*, std::string*>{"senatt", &entry.senatt},
                                     {"axis", &entry.axis},
                                     {"column", &entry.column}}) {
      if (const auto it = value.find(key); it != value.end()) {
        if (!it->is_string()) fail(where + ": \"" + key + "\" must be a string");
        *field = std::string(util::Trim(it->get<std::string>()));
      }
    }
    if (entry.codes.empty() && entry.senatt.empty() && entry.column.empty())
      fail(where + " has neither a \"code\" pattern nor a \"senatt\" nor a \"column\"");
    map.slots.emplace_back(slot, std::move(entry));
  }
  return map;
}

ChannelMap ReadChannelMap(const std::filesystem::path& path) {
  ChannelMap map = ParseChannelMap(ReadJsonFile(path), path.string());
  if (map.name.empty()) map.name = path.stem().string();
  return map;
}

ChannelMap LoadChannelMap(std::string_view name_or_path) {
  return ReadChannelMap(ResolvePreset(PresetKind::kChannelMap, name_or_path));
}

bool CodeMatches(std::string_view pattern, std::string_view code) {
  code = util::Trim(code);
  if (pattern.size() != code.size()) return false;
  for (std::size_t i = 0; i < pattern.size(); ++i)
    if (pattern[i] != '?' && !util::EqualsIgnoreCase(pattern.substr(i, 1), code.substr(i, 1))) return false;
  return true;
}

bool EntryMatches(const ChannelMapEntry& entry, const RawChannel& channel, engine::SensorKind slot_kind) {
  bool matched = false;
  if (!channel.code.empty()) {
    for (const std::string& pattern : entry.codes) matched = matched || CodeMatches(pattern, channel.code);
  } else if (!entry.senatt.empty()) {
    matched = util::EqualsIgnoreCase(util::Trim(channel.senatt), entry.senatt) &&
              (entry.axis.empty() || util::EqualsIgnoreCase(util::Trim(channel.axis), entry.axis));
  }
  if (!matched) return false;
  // The unit tells accelerations from angular rates where codes or SENATT/AXIS
  // alone do not (a UDS-1992 rate sensor may share SENATT and AXIS with the
  // accelerometer of the same axis).
  try {
    const std::optional<SignalUnit> unit = ParseSignalUnit(channel.unit, channel.Label());
    return !unit || unit->kind == slot_kind;
  } catch (const InputError&) {
    return true;  // reported with the slot once the channel is assembled
  }
}

namespace {

// What a channel map entry matches, for a message: "<code> or <code>, or SENATT <senatt> AXIS <axis>".
std::string MatchedChannels(const ChannelMapEntry& entry) {
  std::string wanted;
  for (const std::string& code : entry.codes) {
    if (!wanted.empty()) wanted += " or ";
    wanted += code;
  }
  if (!entry.senatt.empty()) {
    if (!wanted.empty()) wanted += ", or ";
    wanted += "SENATT " + util::QuotedLong(entry.senatt);
    if (!entry.axis.empty()) wanted += " AXIS " + util::QuotedLong(entry.axis);
  }
  return wanted;
}

}  // namespace

std::vector<std::size_t> AssignSlots(const std::vector<RawChannel>& channels,
                                     const engine::ArrayGeometry& array, const ChannelMap& map,
                                     const std::string& test_name) {
  std::vector<std::size_t> assignment;
  for (const engine::Sensor& sensor : array.sensors) {
    const ChannelMapEntry* entry = map.Find(sensor.slot);
    if (entry == nullptr)
      throw InputError("test " + test_name + ": channel map " + util::QuotedLong(map.name) + " (" +
                       map.source + ") has no entry for slot " + util::QuotedLong(sensor.slot) +
                       " of array " + util::QuotedLong(array.name) + ".");
    std::optional<std::size_t> found;
    for (std::size_t c = 0; c < channels.size(); ++c) {
      if (!EntryMatches(*entry, channels[c], sensor.kind)) continue;
      if (found)
        throw InputError("test " + test_name + ": slot " + util::QuotedLong(sensor.slot) +
                         " is matched by two channels, " + channels[*found].Label() + " and " +
                         channels[c].Label() + ".");
      found = c;
    }
    if (!found)
      throw InputError("test " + test_name + ": no channel matches slot " + util::QuotedLong(sensor.slot) +
                       " (" + MatchedChannels(*entry) + ") of channel map " + util::QuotedLong(map.name) +
                       ".");
    for (std::size_t earlier = 0; earlier < assignment.size(); ++earlier)
      if (assignment[earlier] == *found)
        throw InputError("test " + test_name + ": " + channels[*found].Label() + " is matched by both slot " +
                         util::QuotedLong(array.sensors[earlier].slot) + " and slot " +
                         util::QuotedLong(sensor.slot) + " of channel map " + util::QuotedLong(map.name) +
                         ".");
    assignment.push_back(*found);
  }
  return assignment;
}

engine::TestSignals AssembleSignals(const std::vector<RawChannel>& channels,
                                    const std::vector<std::size_t>& channel_of_sensor,
                                    const engine::ArrayGeometry& array, const std::string& test_name,
                                    std::vector<std::string>* notes) {
  if (channel_of_sensor.size() != array.sensors.size() || channel_of_sensor.empty())
    throw InputError("test " + test_name + ": internal error, the slot assignment does not cover the array.");
  const RawChannel& first = channels.at(channel_of_sensor[0]);
  const double dt = first.dt_s;
  double start = -std::numeric_limits<double>::infinity();
  double end = std::numeric_limits<double>::infinity();
  for (const std::size_t c : channel_of_sensor) {
    const RawChannel& channel = channels.at(c);
    if (!(channel.dt_s > 0.0) || !std::isfinite(channel.dt_s))
      throw InputError(channel.Label() + ": the sampling interval " + util::FormatNumber(channel.dt_s) +
                       " s is not a finite positive number.");
    if (std::abs(channel.dt_s - dt) > 1e-6 * dt)
      throw InputError("test " + test_name + ": " + first.Label() + " is sampled every " +
                       util::FormatNumber(dt, 9) + " s but " + channel.Label() + " every " +
                       util::FormatNumber(channel.dt_s, 9) +
                       " s; channels must share the sampling interval.");
    const double offset = (channel.t0_s - first.t0_s) / dt;
    if (std::abs(offset - std::round(offset)) > 1e-3)
      throw InputError("test " + test_name + ": " + channel.Label() + " starts at " +
                       util::FormatNumber(channel.t0_s, 9) + " s, not on the sampling grid of " +
                       first.Label() + " (first sample at " + util::FormatNumber(first.t0_s, 9) + " s).");
    if (channel.values.empty()) throw InputError(channel.Label() + ": the channel has no samples.");
    start = std::max(start, channel.t0_s);
    end = std::min(end, channel.t0_s + static_cast<double>(channel.values.size() - 1) * dt);
  }
  const long long count = std::llround((end - start) / dt) + 1;
  if (!(end >= start) || count < 2)
    throw InputError("test " + test_name +
                     ": the channels do not overlap in time for two samples or more (common span " +
                     util::FormatNumber(start, 9) + " s to " + util::FormatNumber(end, 9) + " s).");
  if (notes != nullptr) {
    // Channels of different spans are cropped to the common span, and the test says so
    // (docs/formats.md "ISO-MME (ISO/TS 13499) input").
    std::string cropped;
    for (const std::size_t c : channel_of_sensor) {
      const RawChannel& channel = channels[c];
      const long long dropped = static_cast<long long>(channel.values.size()) - count;
      if (dropped <= 0) continue;
      const std::string label = !channel.code.empty() ? channel.code : channel.source;
      if (cropped.find(label) != std::string::npos) continue;
      cropped += (cropped.empty() ? "" : ", ") + label + " (" + std::to_string(dropped) + " samples)";
    }
    if (!cropped.empty())
      notes->push_back("test " + test_name +
                       ": the channels' time spans differ; all were cropped to the common span " +
                       util::FormatNumber(start, 9) + " s to " + util::FormatNumber(end, 9) +
                       " s, dropping samples of " + cropped + ".");
  }

  engine::TestSignals signals;
  signals.dt_s = dt;
  // Express the start on the first channel's grid so every channel maps to whole sample indices.
  signals.t0_s = first.t0_s + static_cast<double>(std::llround((start - first.t0_s) / dt)) * dt;
  signals.samples.resize(count, static_cast<Eigen::Index>(array.sensors.size()));
  for (std::size_t s = 0; s < array.sensors.size(); ++s) {
    const engine::Sensor& sensor = array.sensors[s];
    const RawChannel& channel = channels[channel_of_sensor[s]];
    const std::optional<SignalUnit> unit = ParseSignalUnit(channel.unit, channel.Label());
    double scale = 1.0;
    if (unit) {
      if (unit->kind != sensor.kind)
        throw InputError(
            "test " + test_name + ": " + channel.Label() + " in " + util::QuotedLong(channel.unit) +
            " cannot feed slot " + util::QuotedLong(sensor.slot) + ", which is " +
            (sensor.kind == engine::SensorKind::kLinear ? "an accelerometer" : "an angular-rate sensor") +
            ".");
      scale = unit->si_per_unit / sensor.si_per_unit;
    }
    const long long first_index = std::llround((start - channel.t0_s) / dt);
    for (long long k = 0; k < count; ++k)
      signals.samples(k, static_cast<Eigen::Index>(s)) =
          channel.values[static_cast<std::size_t>(first_index + k)] * scale;
    signals.slots.push_back(sensor.slot);
    if (channel.prefiltered_cfc) {
      signals.prefiltered_cfc.resize(array.sensors.size());
      signals.prefiltered_cfc[s] = channel.prefiltered_cfc;
    }
  }
  return signals;
}

}  // namespace napkin::formats
