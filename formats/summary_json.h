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

// {mode, channels: [{channel, fault, action, partner, interval_s, samples_replaced}],
// rms_residual_before_g, rms_residual_after_g, channels_used, channels_total}
// (docs/formats.md "Salvage record"); a residual that could not be computed is null.
nlohmann::ordered_json SalvageToJson(const engine::SalvageAudit& record);

// test_id, series, variant, every field of `query hic` and `query rotation`
// (engine/summary_fields.h), in contract order, then the array `quality`,
// then the object `salvage` (a salvaged result only), then (when the summary
// has one: every processed test) the array `conditioning`. Non-finite numbers become null.
nlohmann::ordered_json SummaryToJson(const engine::TestSummary& summary, const std::string& test_id,
                                     const std::string& series, const std::string& variant);

}  // namespace napkin::formats
