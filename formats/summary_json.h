#pragma once
// Per-test summary as JSON (FORMATS.md "Per-test summary fields"): the
// `transform --summary` file and one object of `query --format json`.
#include <nlohmann/json.hpp>
#include <string>

#include "engine/summary.h"

namespace napkin::formats {

// "info", "warning" or "error".
const char* SeverityText(engine::Severity severity);

// {check, channel (slot or null), severity, detail}
nlohmann::json FindingToJson(const engine::Finding& finding);

// Every field of `query hic` and `query rotation`, in contract order, plus
// the array `quality`. Non-finite numbers become null.
nlohmann::ordered_json SummaryToJson(const engine::TestSummary& summary, const std::string& test_id,
                                     const std::string& series, const std::string& variant);

}  // namespace napkin::formats
