#pragma once
// Per-test summary as JSON (docs/formats.md "Per-test summary fields"): the
// `transform --summary` file and one object of `query --format json`.
#include <nlohmann/json.hpp>
#include <string>

#include "engine/summary.h"

namespace napkin::formats {

// {check, channel (slot or null), severity, detail}, in that order.
nlohmann::ordered_json FindingToJson(const engine::Finding& finding);

// {channel, filter, filter_cfc, prefiltered_cfc, bias_removed, bias_window_s,
// time_shift_s} (docs/formats.md "Conditioning record"); absent values are null.
nlohmann::ordered_json ConditioningToJson(const engine::ChannelConditioning& record);

// test_id, series, variant, every field of `query hic` and `query rotation`
// (engine/summary_fields.h), in contract order, then the array `quality`,
// then (when the summary has one: every processed test) the array
// `conditioning`. Non-finite numbers become null.
nlohmann::ordered_json SummaryToJson(const engine::TestSummary& summary, const std::string& test_id,
                                     const std::string& series, const std::string& variant);

}  // namespace napkin::formats
