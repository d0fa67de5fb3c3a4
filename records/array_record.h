#pragma once
// Accelerometer arrays as catalogue records: the canonical JSON
// (formats::ArrayToJson) and its SHA-256, and back.
#include <filesystem>

#include "db/catalogue.h"
#include "engine/array_geometry.h"
#include "formats/array_json.h"

namespace napkin::records {

// The record of `array`: name, canonical JSON (in metres, so positions read
// back bit-exact) and the SHA-256 of that JSON.
db::ArrayRow MakeArrayRecord(const engine::ArrayGeometry& array);

// The record of `array` as import stores it: MakeArrayRecord, named
// db::HashQualifiedArrayName when a preset of the array's name in
// `config_dir`/arrays holds another definition (an edited copy of
// denton-3222 is not denton-3222: docs/formats.md "Array names in the
// catalogue"). The catalogue qualifies a name another stored array has
// (db::Catalogue::WriteArray).
db::ArrayRow MakeImportedArrayRecord(const engine::ArrayGeometry& array,
                                     const std::filesystem::path& config_dir = formats::DefaultConfigDir());

// Parses and validates a stored array definition. Throws InputError naming
// the array when its JSON is malformed or the array cannot be solved.
engine::ArrayGeometry DecodeArrayRecord(const db::ArrayRow& record);

}  // namespace napkin::records
