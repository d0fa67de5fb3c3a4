#include "formats/array_json.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>
#include <vector>

#include "common/error.h"
#include "common/joined.h"
#include "engine/units.h"
#include "formats/json_file.h"
#include "util/atomic_file.h"
#include "util/text.h"

namespace napkin::formats {
namespace {

using nlohmann::json;

const char* JsonTypeName(const json& value) {
  if (value.is_null()) return "null";
  if (value.is_boolean()) return "a boolean";
  if (value.is_number()) return "a number";
  if (value.is_string()) return "a string";
  if (value.is_array()) return "an array";
  return "an object";
}

// "sensor 3 (slot "yarm_z")" or "sensor 3" while the slot is unknown.
std::string SensorName(std::size_t index, const std::string& slot) {
  std::string name = "sensor " + std::to_string(index + 1);
  if (!slot.empty()) name += " (slot \"" + slot + "\")";
  return name;
}

[[noreturn]] void Fail(const std::string& source, const std::string& problem) {
  throw InvalidArrayError(source + ": " + problem + ".");
}

std::string RequireString(const json& object, const char* key, const std::string& source,
                          const std::string& where) {
  const auto it = object.find(key);
  if (it == object.end()) Fail(source, where + " has no \"" + key + "\"");
  if (!it->is_string()) Fail(source, where + ": \"" + key + "\" must be a string, not " + JsonTypeName(*it));
  return it->get<std::string>();
}

Eigen::Vector3d RequireVector3(const json& value, const char* key, const std::string& source,
                               const std::string& where) {
  if (!value.is_array() || value.size() != 3)
    Fail(source, where + ": \"" + key + "\" must be an array of three numbers");
  Eigen::Vector3d vector;
  for (int i = 0; i < 3; ++i) {
    if (!value[i].is_number()) Fail(source, where + ": \"" + key + "\" must be an array of three numbers");
    vector[i] = value[i].get<double>();
    if (!std::isfinite(vector[i])) Fail(source, where + ": \"" + key + "\" has a non-finite component");
  }
  return vector;
}

// Names are printable and of sane length (util::CheckName).
void CheckJsonName(const std::string& source, const std::string& what, const std::string& name) {
  try {
    util::CheckName(what, name);
  } catch (const InputError& error) {
    std::string problem = error.what();
    problem.pop_back();  // Fail adds the full stop
    Fail(source, problem);
  }
}

// Sensor `index` of the array's "sensors"; `slots` holds the slots of the sensors before it.
engine::Sensor ParseSensor(const json& entry, std::size_t index, const std::string& source,
                           double metres_per_unit, std::set<std::string>& slots) {
  if (!entry.is_object())
    Fail(source, SensorName(index, "") + " must be a JSON object, not " + JsonTypeName(entry));
  engine::Sensor sensor;
  sensor.slot = RequireString(entry, "slot", source, SensorName(index, ""));
  if (sensor.slot.empty()) Fail(source, SensorName(index, "") + " has an empty slot name");
  CheckJsonName(source, SensorName(index, "") + " slot", sensor.slot);
  const std::string where = SensorName(index, sensor.slot);
  if (!slots.insert(sensor.slot).second) Fail(source, where + " duplicates an earlier slot");

  const std::string type = RequireString(entry, "type", source, where);
  const std::optional<engine::SensorKind> kind = engine::ParseName<engine::SensorKind>(type);
  if (!kind) Fail(source, where + " has unknown type \"" + type + "\" (use linear or angular_rate)");
  sensor.kind = *kind;

  sensor.unit = RequireString(entry, "unit", source, where);
  const std::optional<double> si_per_unit = sensor.kind == engine::SensorKind::kLinear
                                                ? engine::LinearUnitToSi(sensor.unit)
                                                : engine::AngularRateUnitToSi(sensor.unit);
  if (!si_per_unit)
    Fail(source, where + " has unknown unit \"" + sensor.unit + "\" for a " + type + " sensor (use " +
                     (sensor.kind == engine::SensorKind::kLinear ? "g or m/s^2" : "rad/s or deg/s") + ")");
  sensor.si_per_unit = *si_per_unit;

  const auto position = entry.find("position");
  if (position != entry.end()) {
    sensor.position_body_m = RequireVector3(*position, "position", source, where) * metres_per_unit;
  } else if (sensor.kind == engine::SensorKind::kLinear) {
    Fail(source, where + " has no \"position\"");
  }
  const auto axis = entry.find("axis");
  if (axis == entry.end()) Fail(source, where + " has no \"axis\"");
  sensor.axis_body = RequireVector3(*axis, "axis", source, where);
  const double norm = sensor.axis_body.norm();
  if (!(norm > 1e-12)) Fail(source, where + " has a zero axis");
  sensor.axis_body /= norm;
  return sensor;
}

}  // namespace

engine::ArrayGeometry ParseArrayJson(const json& root, const std::string& source) {
  if (!root.is_object())
    Fail(source, std::string("an array definition must be a JSON object, not ") + JsonTypeName(root));
  engine::ArrayGeometry array;
  if (root.contains("name")) {
    array.name = RequireString(root, "name", source, "the array");
    CheckJsonName(source, "the array's \"name\"", array.name);
  }
  if (root.contains("description"))
    array.description = RequireString(root, "description", source, "the array");

  const std::string length_unit = RequireString(root, "length_unit", source, "the array");
  const std::optional<double> metres_per_unit = engine::LengthUnitToMetres(length_unit);
  if (!metres_per_unit) Fail(source, "unknown length_unit \"" + length_unit + "\" (use m, mm, cm, in or ft)");

  const auto sensors = root.find("sensors");
  if (sensors == root.end()) Fail(source, "the array has no \"sensors\"");
  if (!sensors->is_array())
    Fail(source, std::string("\"sensors\" must be an array, not ") + JsonTypeName(*sensors));
  if (sensors->empty()) Fail(source, "the array has no sensors");

  std::set<std::string> slots;
  for (std::size_t i = 0; i < sensors->size(); ++i)
    array.sensors.push_back(ParseSensor((*sensors)[i], i, source, *metres_per_unit, slots));
  if (array.name.empty()) array.name = std::filesystem::path(source).stem().string();
  try {
    engine::ValidateArray(array);
  } catch (const InputError& error) {
    throw InvalidArrayError(source + ": " + error.what());
  }
  return array;
}

engine::ArrayGeometry ReadArrayJson(const std::filesystem::path& path) {
  return ParseArrayJson(ReadJsonFile(path), path.string());
}

json ArrayToJson(const engine::ArrayGeometry& array, std::string_view length_unit) {
  const std::optional<double> metres_per_unit = engine::LengthUnitToMetres(length_unit);
  if (!metres_per_unit)
    throw InputError("unknown length unit \"" + std::string(length_unit) + "\" (use m, mm, cm, in or ft).");
  json root = json::object();
  root["name"] = array.name;
  if (!array.description.empty()) root["description"] = array.description;
  root["length_unit"] = std::string(length_unit);
  json sensors = json::array();
  for (const engine::Sensor& sensor : array.sensors) {
    json entry = json::object();
    entry["slot"] = sensor.slot;
    entry["type"] = engine::NameOf(sensor.kind);
    const Eigen::Vector3d position = sensor.position_body_m / *metres_per_unit;
    entry["position"] = {position.x(), position.y(), position.z()};
    entry["axis"] = {sensor.axis_body.x(), sensor.axis_body.y(), sensor.axis_body.z()};
    entry["unit"] = sensor.unit;
    sensors.push_back(std::move(entry));
  }
  root["sensors"] = std::move(sensors);
  return root;
}

void WriteArrayJson(const engine::ArrayGeometry& array, const std::filesystem::path& path,
                    std::string_view length_unit) {
  const std::string text = ArrayToJson(array, length_unit).dump(2) + "\n";
  util::WriteFileAtomically(path, [&](util::AtomicFile& file) { file.Write(text); });
}

engine::ArrayGeometry LoadArray(std::string_view name_or_path) {
  return ReadArrayJson(ResolvePreset(PresetKind::kArray, name_or_path));
}

}  // namespace napkin::formats
