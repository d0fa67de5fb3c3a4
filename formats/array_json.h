#pragma once
// Accelerometer array definitions as JSON (docs/formats.md "Accelerometer array
// definition"; presets in config/arrays/).
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "engine/array_geometry.h"
#include "formats/presets.h"

namespace napkin::formats {

// Reads and validates an array definition: positions to metres
// (length_unit in/mm/m), units to si_per_unit (g, m/s^2, rad/s, deg/s), axes
// normalised, then engine::ValidateArray. Throws InputError (or
// InvalidArrayError) with one sentence naming the file and the sensor slot.
engine::ArrayGeometry ReadArrayJson(const std::filesystem::path& path);

// Same from parsed JSON; `source` names the file in messages.
engine::ArrayGeometry ParseArrayJson(const nlohmann::json& json, const std::string& source);

// The JSON form of `array`, positions expressed in `length_unit` ("in", "mm", "m").
nlohmann::json ArrayToJson(const engine::ArrayGeometry& array, std::string_view length_unit = "in");
void WriteArrayJson(const engine::ArrayGeometry& array, const std::filesystem::path& path,
                    std::string_view length_unit = "in");

// Reads the array preset `name` ("denton-3222") or an array JSON file path.
engine::ArrayGeometry LoadArray(std::string_view name_or_path);

}  // namespace napkin::formats
