#pragma once
// Processing configurations as JSON (presets in config/processing/).
//
//   {
//     "solver": "exact",                       // or "seed"
//     "filter": {"variant": "sae", "linear_cfc": 1000, "angular_rate_cfc": 60, "padding_s": 0.01},
//     "bias": {"mode": "auto", "window_s": [-0.01, 0.0], "auto_min_pre_impact_s": 0.001},
//     "time": {"shift_s": 0.0, "start_s": null, "end_s": null},
//     "gravity": {"compensate": false, "g_fixed": [0, 0, 9.80665]},
//     "hic": {"from_time_zero": false},
//     "a3ms": {"definition": "cumulative"},    // or "continuous"
//     "bric": {"critical_radps": [66.25, 56.45, 42.87]},
//     "screening": {"residual_limit_g": 5, "spike_size_g": 50, "spike_size_radps": 20,
//                   "saturation_run_samples": 5, "bias_limit_g": 1.5, "bias_limit_radps": 0.5},
//     "storage": {"derived_channels": "float32"}  // or "float64" (bit-exact) or "none" (recompute)
//   }
//
// Every key is optional (missing keys keep the defaults of
// engine::ProcessingConfig); unknown keys are errors (a typo must not be
// silently ignored). "filter.*_cfc" takes a class in Hz or "none";
// "filter.variant" is "sae" (J211/1) or "iso" (ISO 6487); "bias.mode" is
// "auto", "window" or "none". Top-level "name" and "description" strings are
// documentation only and not part of the configuration.
//
// The canonical form (ProcessingConfigToJson) has every field, keys sorted
// and numbers as doubles (except the integer saturation_run_samples), so its
// dump identifies the configuration of stored results; "a3ms" and "storage"
// (both added later) only when they are not the default, so earlier
// configurations keep their hash.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "engine/processing.h"

namespace napkin::formats {

// Parses and checks (engine::ProcessingConfig::Check) a configuration.
// Throws InputError with one sentence naming `source` and the key at fault.
engine::ProcessingConfig ParseProcessingConfig(const nlohmann::json& json, const std::string& source);

// Canonical JSON: every field present, keys sorted.
nlohmann::json ProcessingConfigToJson(const engine::ProcessingConfig& config);

// The canonical dump, e.g. for hashing (compact, one line).
std::string CanonicalProcessingConfig(const engine::ProcessingConfig& config);

// Reads a configuration file; errors name the file and the key.
engine::ProcessingConfig ReadProcessingConfig(const std::filesystem::path& path);

}  // namespace napkin::formats

namespace napkin::engine {

// nlohmann::json ADL hooks (j.get<ProcessingConfig>(), json(config)); the
// same rules as ParseProcessingConfig / ProcessingConfigToJson.
void to_json(nlohmann::json& json, const ProcessingConfig& config);
void from_json(const nlohmann::json& json, ProcessingConfig& config);

}  // namespace napkin::engine
