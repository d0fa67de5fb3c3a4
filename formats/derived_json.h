#pragma once
// The derived channels as one JSON object (`export --format json`, GET
// /api/v1/tests/ID/channels?format=json; docs/formats.md "Derived channels"):
// {"test_id": ID, "channels": {COLUMN: [values]}}, one key per derived-channel
// column in CSV order and in the CSV's units (formats/csv.h DerivedChannels),
// every number at full precision (the shortest text that reads back as the
// same double), null for a channel the test does not have and for a
// non-finite sample.
#include <filesystem>
#include <string>

#include "engine/kinematics.h"

namespace napkin::formats {

// The object as one line of text, ending with a newline; text that is not
// UTF-8 (a test id an older napkin stored) has U+FFFD for its bad bytes.
std::string DerivedJsonText(const engine::Kinematics& kinematics, const std::string& test_id);

// Writes DerivedJsonText to `path` atomically (util/atomic_file.h; "-" is standard output).
void WriteDerivedJson(const engine::Kinematics& kinematics, const std::string& test_id,
                      const std::filesystem::path& path);

}  // namespace napkin::formats
