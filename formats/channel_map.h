#pragma once
// Channels read from test files (ISO-MME, UDS-1992, DTS SLICEWare) and the channel map that
// says which channel feeds which array slot (docs/formats.md "ISO-MME input").
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "engine/array_geometry.h"
#include "engine/signals.h"
#include "engine/units.h"

namespace napkin::formats {

// One uniformly sampled channel as read from a file, in its own unit.
struct RawChannel {
  std::string source;  // file the channel came from (for messages)
  std::string code;    // ISO/TS 13499 16-character channel code ("" for UDS-1992)
  std::string name;    // ISO-MME "Name of the channel" / UDS-1992 CURNAM or CURDSC / DTS Channel Description
  std::string senatt;  // UDS-1992 sensor attachment ("" for ISO-MME)
  std::string axis;    // UDS-1992 axis ("XL", ...) ("" for ISO-MME)
  // The dummy the channel belongs to (docs/formats.md "Several dummies in one
  // test"): the ISO-MME code's test object and position ("11", "13"), the
  // UDS-1992 SENLOC ("01", "03"); "" when the file names none.
  std::string position;
  // UDS-1992 INIVEL in m/s along the channel's own axis (nullopt: none recorded).
  std::optional<double> initial_velocity_mps;
  std::string unit;   // as written ("g", "m/s**2", "G'S", "DEG/SEC", ...; "" if none)
  double dt_s = 0.0;  // sampling interval
  double t0_s = 0.0;  // time of the first sample
  // The CFC class the file records the channel as already filtered at
  // (ISO-MME "Channel frequency class" / filter letter, UDS-1992 FCUT); nullopt
  // = raw or not recorded. Becomes engine::TestSignals::prefiltered_cfc.
  std::optional<double> prefiltered_cfc;
  std::vector<double> values;
  // What the file says of the sensor (DTS SLICEWare `Sensor S/N` and `Hardware AA Filter (-3dB)`,
  // as written; "" when it says nothing): kept with the test (docs/formats.md "Test information").
  std::string serial;
  std::string hardware_filter;

  // How messages name the channel: its code, else its file.
  std::string Label() const;
};

using engine::SignalUnit;
// The unit of an ISO-MME or UDS-1992 channel, in the spellings of
// engine::SignalUnitToSi ("g", "G'S", "m/s**2", "M/SEC**2", "rad/s",
// "DEG/SEC", "°/s", ...). nullopt for a blank or NOVALUE unit; throws
// InputError for an unrecognised one (naming `where`).
std::optional<SignalUnit> ParseSignalUnit(std::string_view unit, const std::string& where);

// One slot of a channel map: ISO-MME code patterns ('?' matches any one
// character; a JSON string or an array of alternatives) and/or the UDS-1992
// SENATT and AXIS (trimmed, case-insensitive).
// A CSV signals file is read through the slot's "column" (docs/formats.md
// "CSV input").
struct ChannelMapEntry {
  std::vector<std::string> codes;
  std::string senatt;
  std::string axis;
  std::string column;
};

struct ChannelMap {
  std::string name;
  std::string source;                                          // file it was read from
  std::vector<std::pair<std::string, ChannelMapEntry>> slots;  // in file order

  const ChannelMapEntry* Find(std::string_view slot) const;
  // The slots with a "column" entry: slot -> CSV column name, in map order.
  std::vector<std::pair<std::string, std::string>> CsvColumns() const;
};

// Reads a channel map; throws InputError naming the file and the slot at fault.
ChannelMap ReadChannelMap(const std::filesystem::path& path);
ChannelMap ParseChannelMap(const nlohmann::json& json, const std::string& source);
// A preset name from config/channel-maps/ ("default", "nap-example") or a path.
ChannelMap LoadChannelMap(std::string_view name_or_path);

// ISO-MME code match: same length, '?' in the pattern matches any character,
// other characters compare case-insensitively.
bool CodeMatches(std::string_view pattern, std::string_view code);

// Whether `entry` selects `channel`: by code for ISO-MME channels, by SENATT
// and AXIS for UDS-1992 channels; a channel whose unit shows the wrong
// physical kind for the slot (an acceleration for a rate slot) never matches.
bool EntryMatches(const ChannelMapEntry& entry, const RawChannel& channel, engine::SensorKind slot_kind);

// For every sensor of `array`, the index in `channels` of the one channel the
// map assigns to it. Throws InputError naming the slot when the map has no
// entry for it, or no channel or two channels match.
std::vector<std::size_t> AssignSlots(const std::vector<RawChannel>& channels,
                                     const engine::ArrayGeometry& array, const ChannelMap& map,
                                     const std::string& test_name);

// Builds the test's signals: channel_of_sensor[i] feeds array.sensors[i].
// Channels must share the sampling interval (error naming both channels) and
// lie on one time grid that they share for at least two samples; the result
// covers the common time span, each value converted into the unit the array
// gives the slot, with each channel's prefiltered_cfc. When the channels'
// spans differ, one sentence saying what was cropped is added to `notes` (if
// given).
engine::TestSignals AssembleSignals(const std::vector<RawChannel>& channels,
                                    const std::vector<std::size_t>& channel_of_sensor,
                                    const engine::ArrayGeometry& array, const std::string& test_name,
                                    std::vector<std::string>* notes = nullptr);

}  // namespace napkin::formats
