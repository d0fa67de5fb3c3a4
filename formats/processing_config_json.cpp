#include "formats/processing_config_json.h"

#include <algorithm>
#include <array>
#include <initializer_list>
#include <sstream>
#include <string_view>

#include "common/error.h"
#include "formats/json_file.h"
#include "util/text.h"

namespace napkin::formats {

namespace {

using nlohmann::json;

// Reads one JSON object of the configuration; every message names the
// source and the full key path.
class ObjectReader {
 public:
  ObjectReader(const json& object, std::string prefix, const std::string& source,
               std::initializer_list<std::string_view> allowed)
      : object_(object), prefix_(std::move(prefix)), source_(source) {
    if (!object.is_object()) Fail(prefix_.empty() ? "" : prefix_, "an object");
    for (const auto& [key, value] : object.items()) {
      if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
        std::ostringstream message;
        message << source_ << ": unknown key \"" << Path(key) << "\".";
        throw InputError(message.str());
      }
    }
  }

  const json* Find(const std::string& key) const {
    const auto it = object_.find(key);
    return it == object_.end() ? nullptr : &*it;
  }

  std::string Path(const std::string& key) const { return prefix_.empty() ? key : prefix_ + "." + key; }

  [[noreturn]] void Fail(const std::string& key_path, const std::string& requirement) const {
    std::ostringstream message;
    if (key_path.empty())
      message << source_ << ": the configuration must be " << requirement << ".";
    else
      message << source_ << ": key \"" << key_path << "\" must be " << requirement << ".";
    throw InputError(message.str());
  }

  void Number(const std::string& key, double& out) const {
    if (const json* value = Find(key)) {
      if (!value->is_number()) Fail(Path(key), "a number");
      out = value->get<double>();
    }
  }

  void Integer(const std::string& key, int& out) const {
    if (const json* value = Find(key)) {
      if (!value->is_number_integer()) Fail(Path(key), "an integer");
      const auto wide = value->get<long long>();
      if (wide < -1000000000LL || wide > 1000000000LL) Fail(Path(key), "an integer of reasonable size");
      out = static_cast<int>(wide);
    }
  }

  void Bool(const std::string& key, bool& out) const {
    if (const json* value = Find(key)) {
      if (!value->is_boolean()) Fail(Path(key), "true or false");
      out = value->get<bool>();
    }
  }

  // A number or null (null = not set).
  void OptionalNumber(const std::string& key, std::optional<double>& out) const {
    if (const json* value = Find(key)) {
      if (value->is_null())
        out.reset();
      else if (value->is_number())
        out = value->get<double>();
      else
        Fail(Path(key), "a number or null");
    }
  }

  // A CFC class in Hz or "none".
  void FilterClass(const std::string& key, std::optional<double>& out) const {
    if (const json* value = Find(key)) {
      if (value->is_string() && value->get<std::string>() == "none")
        out.reset();
      else if (value->is_number())
        out = value->get<double>();
      else
        Fail(Path(key), "a filter class in Hz (e.g. 1000) or \"none\"");
    }
  }

  void Vector3(const std::string& key, Eigen::Vector3d& out) const {
    if (const json* value = Find(key)) {
      if (!value->is_array() || value->size() != 3 ||
          !std::all_of(value->begin(), value->end(), [](const json& v) { return v.is_number(); }))
        Fail(Path(key), "an array of 3 numbers");
      for (int i = 0; i < 3; ++i) out[i] = (*value)[static_cast<std::size_t>(i)].get<double>();
    }
  }

  // A name of one of the engine's vocabularies (engine/vocabulary.h), `all`
  // its values (listed when the name is unknown).
  template <typename Enum, std::size_t N>
  void Choice(const std::string& key, Enum& out, const std::array<Enum, N>& all) const {
    if (const json* value = Find(key)) {
      if (value->is_string()) {
        if (const std::optional<Enum> choice = engine::ParseName<Enum>(value->get<std::string>())) {
          out = *choice;
          return;
        }
      }
      std::string requirement = "one of";
      bool first = true;
      for (const Enum choice : all) {
        requirement += (first ? " \"" : ", \"") + std::string(engine::NameOf(choice)) + "\"";
        first = false;
      }
      Fail(Path(key), requirement);
    }
  }

  // A nested object, or nullptr when absent.
  const json* Object(const std::string& key) const {
    const json* value = Find(key);
    if (value && !value->is_object()) Fail(Path(key), "an object");
    return value;
  }

 private:
  const json& object_;
  std::string prefix_;
  const std::string& source_;
};

json Vector3Json(const Eigen::Vector3d& v) { return json::array({v[0], v[1], v[2]}); }

json OptionalJson(const std::optional<double>& value) { return value ? json(*value) : json(nullptr); }

json FilterClassJson(const std::optional<double>& value) { return value ? json(*value) : json("none"); }

}  // namespace

engine::ProcessingConfig ParseProcessingConfig(const nlohmann::json& json, const std::string& source) {
  engine::ProcessingConfig config;
  const ObjectReader top(json, "", source,
                         {"name", "description", "solver", "filter", "bias", "time", "gravity", "hic", "a3ms",
                          "bric", "screening", "plausibility", "storage"});
  for (const char* key : {"name", "description"})
    if (const auto* value = top.Find(key); value && !value->is_string()) top.Fail(key, "a string");
  if (const auto* name = top.Find("name")) util::CheckName(source + ": \"name\"", name->get<std::string>());
  top.Choice("solver", config.solver, engine::kSolverKinds);

  if (const auto* object = top.Object("filter")) {
    const ObjectReader filter(*object, "filter", source,
                              {"variant", "linear_cfc", "angular_rate_cfc", "padding_s"});
    filter.Choice("variant", config.filter.variant, engine::kCfcVariants);
    filter.FilterClass("linear_cfc", config.filter.linear_cfc);
    filter.FilterClass("angular_rate_cfc", config.filter.angular_rate_cfc);
    filter.Number("padding_s", config.filter.padding_s);
  }
  if (const auto* object = top.Object("bias")) {
    const ObjectReader bias(*object, "bias", source, {"mode", "window_s", "auto_min_pre_impact_s"});
    bias.Choice("mode", config.bias.mode, engine::kBiasModes);
    if (const auto* window = bias.Find("window_s")) {
      if (!window->is_array() || window->size() != 2 || !(*window)[0].is_number() ||
          !(*window)[1].is_number())
        bias.Fail("bias.window_s", "an array of 2 numbers [start, end] in seconds");
      config.bias.window_start_s = (*window)[0].get<double>();
      config.bias.window_end_s = (*window)[1].get<double>();
    }
    bias.Number("auto_min_pre_impact_s", config.bias.auto_min_pre_impact_s);
  }
  if (const auto* object = top.Object("time")) {
    const ObjectReader time(*object, "time", source, {"shift_s", "start_s", "end_s"});
    time.Number("shift_s", config.time.shift_s);
    time.OptionalNumber("start_s", config.time.start_s);
    time.OptionalNumber("end_s", config.time.end_s);
  }
  if (const auto* object = top.Object("gravity")) {
    const ObjectReader gravity(*object, "gravity", source, {"compensate", "g_fixed"});
    gravity.Bool("compensate", config.gravity.compensate);
    gravity.Vector3("g_fixed", config.gravity.g_fixed_mps2);
  }
  if (const auto* object = top.Object("hic")) {
    const ObjectReader hic(*object, "hic", source, {"from_time_zero"});
    hic.Bool("from_time_zero", config.hic.from_time_zero);
  }
  if (const auto* object = top.Object("a3ms")) {
    const ObjectReader a3ms(*object, "a3ms", source, {"definition"});
    a3ms.Choice("definition", config.a3ms.definition, engine::kA3msDefinitions);
  }
  if (const auto* object = top.Object("bric")) {
    const ObjectReader bric(*object, "bric", source, {"critical_radps"});
    bric.Vector3("critical_radps", config.bric.critical_radps);
  }
  if (const auto* object = top.Object("screening")) {
    const ObjectReader screening(*object, "screening", source,
                                 {"residual_limit_g", "spike_size_g", "spike_size_radps",
                                  "saturation_run_samples", "bias_limit_g", "bias_limit_radps", "salvage"});
    screening.Number("residual_limit_g", config.screening.residual_limit_g);
    screening.Number("spike_size_g", config.screening.spike_size_g);
    screening.Number("spike_size_radps", config.screening.spike_size_radps);
    screening.Integer("saturation_run_samples", config.screening.saturation_run_samples);
    screening.Number("bias_limit_g", config.screening.bias_limit_g);
    screening.Number("bias_limit_radps", config.screening.bias_limit_radps);
    screening.Choice("salvage", config.screening.salvage, engine::kSalvageModes);
  }
  if (const auto* object = top.Object("plausibility")) {
    const ObjectReader plausibility(
        *object, "plausibility", source,
        {"max_acceleration_g", "max_angular_velocity_radps", "max_residual_factor", "max_initial_speed_mps"});
    plausibility.Number("max_acceleration_g", config.plausibility.max_acceleration_g);
    plausibility.Number("max_angular_velocity_radps", config.plausibility.max_angular_velocity_radps);
    plausibility.Number("max_residual_factor", config.plausibility.max_residual_factor);
    plausibility.Number("max_initial_speed_mps", config.plausibility.max_initial_speed_mps);
  }
  if (const auto* object = top.Object("storage")) {
    const ObjectReader storage(*object, "storage", source, {"derived_channels"});
    storage.Choice("derived_channels", config.storage.derived_channels, engine::kDerivedStorages);
  }

  try {
    config.Check();
  } catch (const InputError& error) {
    // Check() says "processing config key ...": name the source instead.
    std::string what = error.what();
    const std::string generic = "processing config ";
    if (what.rfind(generic, 0) == 0) what.erase(0, generic.size());
    throw InputError(source + ": " + what);
  }
  return config;
}

nlohmann::json ProcessingConfigToJson(const engine::ProcessingConfig& config) {
  json out = json::object();
  out["solver"] = engine::NameOf(config.solver);
  out["filter"] = {{"variant", engine::NameOf(config.filter.variant)},
                   {"linear_cfc", FilterClassJson(config.filter.linear_cfc)},
                   {"angular_rate_cfc", FilterClassJson(config.filter.angular_rate_cfc)},
                   {"padding_s", config.filter.padding_s}};
  out["bias"] = {{"mode", engine::NameOf(config.bias.mode)},
                 {"window_s", json::array({config.bias.window_start_s, config.bias.window_end_s})},
                 {"auto_min_pre_impact_s", config.bias.auto_min_pre_impact_s}};
  out["time"] = {{"shift_s", config.time.shift_s},
                 {"start_s", OptionalJson(config.time.start_s)},
                 {"end_s", OptionalJson(config.time.end_s)}};
  out["gravity"] = {{"compensate", config.gravity.compensate},
                    {"g_fixed", Vector3Json(config.gravity.g_fixed_mps2)}};
  out["hic"] = {{"from_time_zero", config.hic.from_time_zero}};
  // Added after results were first stored: present only when not the default
  // (cumulative), so every earlier configuration keeps its canonical form and hash.
  if (config.a3ms.definition != engine::ProcessingConfig{}.a3ms.definition)
    out["a3ms"] = {{"definition", engine::NameOf(config.a3ms.definition)}};
  out["bric"] = {{"critical_radps", Vector3Json(config.bric.critical_radps)}};
  out["screening"] = {{"residual_limit_g", config.screening.residual_limit_g},
                      {"spike_size_g", config.screening.spike_size_g},
                      {"spike_size_radps", config.screening.spike_size_radps},
                      {"saturation_run_samples", config.screening.saturation_run_samples},
                      {"bias_limit_g", config.screening.bias_limit_g},
                      {"bias_limit_radps", config.screening.bias_limit_radps}};
  // Added after results were first stored: present only when not the default
  // (off), as "a3ms" above; salvaged results thus carry their own config hash.
  if (config.screening.salvage != engine::SalvageMode::kOff)
    out["screening"]["salvage"] = engine::NameOf(config.screening.salvage);
  out["plausibility"] = {{"max_acceleration_g", config.plausibility.max_acceleration_g},
                         {"max_angular_velocity_radps", config.plausibility.max_angular_velocity_radps},
                         {"max_residual_factor", config.plausibility.max_residual_factor},
                         {"max_initial_speed_mps", config.plausibility.max_initial_speed_mps}};
  // Added after results were first stored: present only when not the default
  // (float32), as "a3ms" above. Each stored derived channel records its own
  // encoding (docs/formats.md "Derived-channel storage").
  if (config.storage.derived_channels != engine::ProcessingConfig{}.storage.derived_channels)
    out["storage"] = {{"derived_channels", engine::NameOf(config.storage.derived_channels)}};
  return out;
}

std::string CanonicalProcessingConfig(const engine::ProcessingConfig& config) {
  return ProcessingConfigToJson(config).dump();
}

engine::ProcessingConfig ReadProcessingConfig(const std::filesystem::path& path) {
  const std::string source = "processing config file " + path.string();
  const std::string text = ReadWholeFile(path, kMaxJsonFileBytes);
  json parsed;
  try {
    parsed = json::parse(text);
  } catch (const json::exception& error) {  // syntax, or a number beyond double's range (fuzz/)
    throw InputError(source + " is not valid JSON (" + util::Abbreviated(error.what(), 200) + ").");
  }
  return ParseProcessingConfig(parsed, source);
}

}  // namespace napkin::formats

namespace napkin::engine {

void to_json(nlohmann::json& json, const ProcessingConfig& config) {
  json = formats::ProcessingConfigToJson(config);
}

void from_json(const nlohmann::json& json, ProcessingConfig& config) {
  config = formats::ParseProcessingConfig(json, "processing config");
}

}  // namespace napkin::engine
