#include "ingest/dummy_heads.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <utility>

#include "common/error.h"
#include "formats/array_json.h"
#include "ingest/array_from_codes.h"
#include "ingest/zip_input.h"
#include "util/text.h"

namespace napkin::ingest {
namespace {

std::string PositionList(const std::vector<std::string>& positions) {
  std::string list;
  for (std::size_t i = 0; i < positions.size(); ++i)
    list += (i == 0 ? "" : i + 1 == positions.size() ? " and " : ", ") + positions[i];
  return list;
}

// The positions of the channels some slot of `map` matches, in order.
std::vector<std::string> MatchedPositions(const std::vector<formats::RawChannel>& channels,
                                          const engine::ArrayGeometry& array,
                                          const formats::ChannelMap& map) {
  std::set<std::string> positions;
  for (const engine::Sensor& sensor : array.sensors) {
    const formats::ChannelMapEntry* entry = map.Find(sensor.slot);
    if (entry == nullptr) continue;
    for (const formats::RawChannel& channel : channels)
      if (formats::EntryMatches(*entry, channel, sensor.kind)) positions.insert(channel.position);
  }
  return {positions.begin(), positions.end()};
}

// A channel's description without its samples (what AssignSlots looks at).
formats::RawChannel Described(const formats::RawChannel& channel) {
  formats::RawChannel described;
  described.source = channel.source;
  described.code = channel.code;
  described.name = channel.name;
  described.senatt = channel.senatt;
  described.axis = channel.axis;
  described.unit = channel.unit;
  described.position = channel.position;
  described.serial = channel.serial;
  described.hardware_filter = channel.hardware_filter;
  return described;
}

}  // namespace

DummyHeadSearch FindDummyHeads(const std::vector<formats::RawChannel>& channels,
                               const engine::ArrayGeometry& array, const formats::ChannelMap& map,
                               const std::string& test_name) {
  DummyHeadSearch search;
  const std::vector<std::string> positions = MatchedPositions(channels, array, map);
  if (positions.size() <= 1) {
    search.heads.push_back(
        {positions.empty() ? "" : positions.front(), formats::AssignSlots(channels, array, map, test_name)});
    return search;
  }
  std::optional<std::string> first_error;
  const std::string head_name_prefix = test_name + "/";  // a head is named "<test>/<position>"
  for (const std::string& position : positions) {
    std::vector<formats::RawChannel> own;
    std::vector<std::size_t> index_in_test;
    for (std::size_t c = 0; c < channels.size(); ++c) {
      if (channels[c].position != position) continue;
      own.push_back(Described(channels[c]));
      index_in_test.push_back(c);
    }
    try {
      DummyHead head{position, formats::AssignSlots(own, array, map, head_name_prefix + position)};
      for (std::size_t& c : head.channel_of_sensor) c = index_in_test[c];
      search.heads.push_back(std::move(head));
    } catch (const InputError& error) {
      if (!first_error) first_error = error.what();
      search.warnings.push_back(std::string(error.what()) + " Position " + position +
                                " is not imported: its channels do not feed every slot of array \"" +
                                array.name + "\".");
    }
  }
  if (search.heads.empty()) throw InputError(*first_error);
  return search;
}

FileInitialVelocity InitialVelocityBody(const std::vector<formats::RawChannel>& channels,
                                        const std::vector<std::size_t>& channel_of_sensor,
                                        const engine::ArrayGeometry& array,
                                        const Eigen::Vector3d& omega_body_radps) {
  struct Candidate {
    const formats::RawChannel* channel;
    const engine::Sensor* sensor;
    double cg_velocity_mps;  // the CG velocity along the body axis this sensor gives
  };
  std::array<std::vector<Candidate>, 3> by_axis;
  FileInitialVelocity result;
  auto described = [](const formats::RawChannel& channel, const engine::Sensor& sensor) {
    return channel.Label() + " (slot " + sensor.slot + ", INIVEL " +
           util::FormatNumber(*channel.initial_velocity_mps) + " m/s)";
  };
  for (std::size_t s = 0; s < array.sensors.size() && s < channel_of_sensor.size(); ++s) {
    const engine::Sensor& sensor = array.sensors[s];
    const formats::RawChannel& channel = channels.at(channel_of_sensor[s]);
    if (!channel.initial_velocity_mps) continue;
    if (sensor.kind != engine::SensorKind::kLinear) {
      result.unused.push_back(described(channel, sensor) +
                              ": INIVEL is not used, as it is a linear velocity and the channel feeds an "
                              "angular-rate sensor.");
      continue;
    }
    int axis = -1;
    for (int a = 0; a < 3; ++a)
      if (std::abs(std::abs(sensor.axis_body[a]) - 1.0) <= 1e-12) axis = a;
    if (axis < 0) {
      result.unused.push_back(described(channel, sensor) +
                              ": INIVEL is not used, as the sensor senses along no body axis.");
      continue;
    }
    // INIVEL = axis . (v_CG + omega x r): the CG's velocity along the axis is INIVEL - axis . (omega x r).
    const double along_sense =
        *channel.initial_velocity_mps - sensor.axis_body.dot(omega_body_radps.cross(sensor.position_body_m));
    by_axis[static_cast<std::size_t>(axis)].push_back(
        {&channel, &sensor, along_sense * sensor.axis_body[axis]});
  }
  const char* axis_names[3] = {"x", "y", "z"};
  for (std::size_t a = 0; a < 3; ++a) {
    std::vector<Candidate>& candidates = by_axis[a];
    if (candidates.empty()) continue;
    // The sensor nearest the CG (the first of equals, in the array's order).
    std::stable_sort(candidates.begin(), candidates.end(), [](const Candidate& p, const Candidate& q) {
      return p.sensor->position_body_m.norm() < q.sensor->position_body_m.norm();
    });
    const Candidate& used = candidates.front();
    if (!result.velocity_body_mps) result.velocity_body_mps = Eigen::Vector3d::Zero();
    (*result.velocity_body_mps)[static_cast<Eigen::Index>(a)] = used.cg_velocity_mps;
    for (std::size_t c = 1; c < candidates.size(); ++c) {
      // INIVEL is a REAL*4: channels that agree to its precision say the same.
      const double difference = std::abs(candidates[c].cg_velocity_mps - used.cg_velocity_mps);
      if (difference <= 1e-6 * std::max(1.0, std::abs(used.cg_velocity_mps))) continue;
      result.unused.push_back(described(*candidates[c].channel, *candidates[c].sensor) +
                              ": INIVEL is not used, as it differs from the " + axis_names[a] +
                              " velocity taken from " + used.channel->Label() + " (slot " +
                              used.sensor->slot + "), the sensor nearest the CG.");
    }
  }
  return result;
}

namespace {

// The sensors of one head as the files record them (serials, hardware filters), in slot order.
std::vector<formats::SensorInfo> SensorsOf(const std::vector<formats::RawChannel>& channels,
                                           const std::vector<std::size_t>& channel_of_sensor,
                                           const engine::ArrayGeometry& array) {
  std::vector<formats::SensorInfo> sensors;
  bool recorded = false;
  for (std::size_t s = 0; s < array.sensors.size(); ++s) {
    const formats::RawChannel& channel = channels.at(channel_of_sensor[s]);
    recorded = recorded || !channel.serial.empty() || !channel.hardware_filter.empty();
    sensors.push_back({array.sensors[s].slot, channel.code, channel.serial, channel.hardware_filter});
  }
  if (!recorded) sensors.clear();
  return sensors;
}

InputHeads ReadArchiveHeads(const ImportInput& input, const HeadReadOptions& options,
                            const std::string& test_name) {
  const ArchiveTest archive(input.source);  // its temporary folder is removed on leaving
  InputHeads inside;
  try {
    inside = ReadInputHeads(archive.input(), options, test_name);
  } catch (const InputError& error) {
    throw InputError(archive.InArchiveTerms(error.what()));
  }
  inside.test_id.reset();  // the archive names the test (docs/formats.md "Zip archives")
  for (std::string& warning : inside.warnings) warning = archive.InArchiveTerms(warning);
  for (HeadSignals& head : inside.heads) {
    head.archived_format = archive.input().format;
    for (std::string& note : head.notes) note = archive.InArchiveTerms(note);
  }
  return inside;
}

InputHeads ReadSlotColumnHeads(const ImportInput& input, const HeadReadOptions& options,
                               const std::string& test_name) {
  const InputFormatEntry& format = FormatEntry(input.format);
  // A missing option (exit 2), as --array was when every input needed it.
  if (options.array == nullptr)
    throw UsageError("test " + test_name + ": a " + std::string(format.title) +
                     " file names slots, not sensors, so its array must be given (" + options.array_option +
                     ").");
  if (options.position)
    throw InputError("test " + test_name + ": --position " + *options.position +
                     " takes one dummy of a test that records several; a " + std::string(format.title) +
                     " file holds one.");
  InputHeads result;
  result.array = *options.array;
  formats::CsvSignals csv = formats::ReadSignalsCsv(input.source, &result.array, options.csv_columns);
  HeadSignals head;
  head.signals = std::move(csv.signals);
  result.warnings = std::move(csv.warnings);
  result.heads.push_back(std::move(head));
  return result;
}

}  // namespace

InputHeads ReadInputHeads(const ImportInput& input, const HeadReadOptions& options,
                          const std::string& test_name) {
  const InputFormatEntry& format = FormatEntry(input.format);
  switch (format.reader_kind) {
    case ReaderKind::kArchive:
      return ReadArchiveHeads(input, options, test_name);
    case ReaderKind::kSlotColumns:
      return ReadSlotColumnHeads(input, options, test_name);
    case ReaderKind::kChannels:
      break;
  }

  InputHeads result;
  ChannelRecording recording = format.read_channels(input);
  std::vector<formats::RawChannel>& channels = recording.channels;
  result.warnings = std::move(recording.warnings);
  result.test_id = recording.test_id;
  const std::string name = recording.name.empty() ? test_name : recording.name;
  if (options.array != nullptr) {
    result.array = *options.array;
  } else if (format.array_from_codes) {
    const std::string preset = ArrayPresetFromCodes(channels, name, options.array_option);
    result.array = formats::ReadArrayJson(formats::ResolvePreset(
        formats::PresetKind::kArray, preset,
        options.config_dir.empty() ? formats::DefaultConfigDir() : options.config_dir));
    result.array_from_codes = true;
  } else {
    throw UsageError(
        "test " + name + ": " + std::string(format.title) +
        " channels carry no ISO/TS 13499 codes that could define the array, so it must be given (" +
        options.array_option + ").");
  }
  const engine::ArrayGeometry& array = result.array;
  const formats::ChannelMap* map = options.channel_map != nullptr ? options.channel_map : options.default_map;
  std::vector<DummyHead> heads;
  if (options.channel_map == nullptr && format.assignment_by_order != nullptr) {
    if (std::optional<std::vector<std::size_t>> by_order =
            format.assignment_by_order(recording, array, test_name)) {
      heads.push_back({"", std::move(*by_order)});
      map = nullptr;
    }
  }
  if (map != nullptr) {
    try {
      DummyHeadSearch search = FindDummyHeads(channels, array, *map, name);
      heads = std::move(search.heads);
      result.warnings.insert(result.warnings.end(), search.warnings.begin(), search.warnings.end());
    } catch (const InputError& error) {
      if (format.default_map_refusal == nullptr || options.channel_map != nullptr) throw;
      throw format.default_map_refusal(error, channels.size(), name);
    }
  }

  std::vector<std::string> positions;
  positions.reserve(heads.size());
  for (const DummyHead& head : heads) positions.push_back(head.position);
  if (options.position) {
    const auto chosen = std::find(positions.begin(), positions.end(), *options.position);
    if (chosen == positions.end())
      throw InputError("test " + test_name + " has no dummy head at position " + *options.position + " (" +
                       (heads.size() == 1 && heads.front().position.empty()
                            ? std::string("its channels name no position")
                            : "it holds position " + PositionList(positions)) +
                       ").");
    heads = {heads[static_cast<std::size_t>(chosen - positions.begin())]};
  } else if (heads.size() > 1 && options.one_test_expected) {
    throw InputError("test " + test_name + " holds dummy heads at positions " + PositionList(positions) +
                     " but " + *options.one_test_expected + "; give --position to take one.");
  }
  result.several = positions.size() > 1;

  for (const DummyHead& dummy : heads) {
    HeadSignals head;
    head.position = dummy.position;
    head.signals = formats::AssembleSignals(channels, dummy.channel_of_sensor, array,
                                            result.several ? name + "/" + dummy.position : name, &head.notes);
    head.info = recording.info_of_channel.at(dummy.channel_of_sensor.front());
    head.info.sensors = SensorsOf(channels, dummy.channel_of_sensor, array);
    FileInitialVelocity inivel =
        InitialVelocityBody(channels, dummy.channel_of_sensor, array, options.initial_omega_body_radps);
    head.initial_velocity_body_mps = inivel.velocity_body_mps;
    result.warnings.insert(result.warnings.end(), inivel.unused.begin(), inivel.unused.end());
    if (map != nullptr) head.channel_map = map->name;
    result.heads.push_back(std::move(head));
  }
  return result;
}

formats::CsvColumnMap CsvColumnsOf(const formats::ChannelMap* map,
                                   const std::vector<std::string>& column_options) {
  formats::CsvColumnMap columns = map != nullptr ? map->CsvColumns() : formats::CsvColumnMap{};
  for (auto& [slot, column] : formats::ParseCsvColumnOptions(column_options)) {
    // A named copy: clang 14 (the `make fuzz` build) cannot capture a structured binding.
    const std::string& named_slot = slot;
    std::erase_if(columns, [&](const auto& mapped) { return mapped.first == named_slot; });
    columns.emplace_back(slot, column);
  }
  return columns;
}

}  // namespace napkin::ingest
