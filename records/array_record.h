#pragma once
// Accelerometer arrays as catalogue records: the canonical JSON
// (formats::ArrayToJson) and its SHA-256, and back.
#include "db/catalogue.h"
#include "engine/array_geometry.h"

namespace napkin::records {

// The record of `array`: name, canonical JSON (in metres, so positions read
// back bit-exact) and the SHA-256 of that JSON.
db::ArrayRow MakeArrayRecord(const engine::ArrayGeometry& array);

// Parses and validates a stored array definition. Throws InputError naming
// the array when its JSON is malformed or the array cannot be solved.
engine::ArrayGeometry DecodeArrayRecord(const db::ArrayRow& record);

}  // namespace napkin::records
