// The presets, the limit sets and the chance of a further test (docs/python.md
// "Presets", "Limits"): napkin.presets, napkin.LIMITS and
// napkin.exceed_probability, over formats/presets.h, app/limits.h and
// engine/prediction.h, the functions the command uses.
#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <vector>

#include "app/limits.h"
#include "engine/prediction.h"
#include "formats/presets.h"
#include "python/py_bindings.h"

namespace napkin::python {
namespace {

// Each preset of config/limits: (preset, name, title, applies_to, source, url, version, note, path).
std::vector<py::tuple> LimitPresetRows() {
  std::vector<py::tuple> rows;
  for (const std::string& preset : app::LimitPresets()) {
    const app::LimitSet set = app::LoadLimits(preset);
    rows.push_back(py::make_tuple(preset, set.name, set.title, set.applies_to, set.source, set.url,
                                  set.version, set.note, set.path.string()));
  }
  return rows;
}

// P(a further test > limit) from `values` (engine::ExceedProbability), NaN
// where not estimated (fewer than 3 values, a value <= 0, no spread).
double ExceedProbability(const py::handle& values, double limit) {
  const auto array = AsFloatArray(values, "napkin.exceed_probability: values");
  if (array.ndim() != 1) throw py::value_error("napkin.exceed_probability: values is not a 1-D array.");
  if (!(limit > 0.0) || !std::isfinite(limit))
    throw py::value_error("napkin.exceed_probability: limit must be a positive number.");
  const std::vector<double> samples(array.data(), array.data() + array.shape(0));
  for (const double sample : samples)
    if (!std::isfinite(sample))
      throw py::value_error("napkin.exceed_probability: values holds a NaN or infinity.");
  const engine::PredictiveFit fit = engine::FitLogPredictive(samples);
  if (!fit.predictive) return std::numeric_limits<double>::quiet_NaN();
  return engine::ExceedProbability(*fit.predictive, limit);
}

}  // namespace

void RegisterLimits(py::module_& module) {
  // The configuration folder and a kind's presets as every reader finds them (formats/presets.h):
  // Python searches no folder of its own.
  module.def("_config_dir",
             [] { return Translated("", [] { return formats::DefaultConfigDir().string(); }); });
  module.def(
      "_presets",
      [](const std::string& kind) {
        return Translated("", [&] { return formats::PresetNames(formats::PresetKindNamed(kind)); });
      },
      py::arg("kind"));
  module.def("_limit_presets", [] { return Translated("", [] { return LimitPresetRows(); }); });
  module.def(
      "exceed_probability", &ExceedProbability, py::arg("values"), py::arg("limit"),
      "The chance that a further test exceeds `limit`, from the variant's values on the log scale: "
      "1 - T_{n-1}((ln limit - m) / (s sqrt(1 + 1/n))), m and s the mean and sd of the logs; NaN where "
      "not estimated (fewer than 3 values, a value <= 0, no spread).");
}

}  // namespace napkin::python
