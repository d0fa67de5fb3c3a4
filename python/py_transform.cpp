// napkin.transform: one test's raw signals from numpy arrays through the
// pipeline `napkin transform` runs (engine::ProcessTest, engine::FailingFinding)
// to its summary JSON and derived channels (docs/python.md "transform").
#include <pybind11/stl.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "common/error.h"
#include "common/joined.h"
#include "engine/pipeline.h"
#include "engine/solver.h"
#include "formats/array_json.h"
#include "formats/csv.h"
#include "formats/processing_config_json.h"
#include "formats/summary_json.h"
#include "python/py_bindings.h"
#include "records/config_record.h"
#include "util/malloc_tuning.h"
#include "util/text.h"

namespace napkin::python {
namespace {

// What a bad-input sentence starts with: the test id when the caller gave one
// (as the CLI names the input file), else the function.
std::string Source(const std::string& test_id) { return test_id.empty() ? "napkin.transform" : test_id; }

// A preset or JSON file read once per version of the file (its modification
// time and size): a loop over thousands of tests must not read, parse and
// check the same array and config for each (bench/run_python.sh). Called with
// the GIL held, which serialises the callers.
template <typename Value>
Value ReadOnce(const std::filesystem::path& path, Value (*read)(const std::filesystem::path&)) {
  struct Entry {
    std::filesystem::file_time_type modified;
    std::uintmax_t size = 0;
    Value value;
  };
  static std::map<std::filesystem::path, Entry> cache;
  std::error_code error;
  const std::filesystem::path key = std::filesystem::absolute(path, error);
  const auto modified = std::filesystem::last_write_time(path, error);
  const std::uintmax_t size = error ? 0 : std::filesystem::file_size(path, error);
  if (error) return read(path);  // read() says what is wrong with it
  const auto found = cache.find(key);
  if (found != cache.end() && found->second.modified == modified && found->second.size == size)
    return found->second.value;
  return cache.insert_or_assign(key, Entry{modified, size, read(path)}).first->second.value;
}

// The array `array` names: an array definition's JSON text (what
// napkin/__init__.py makes of a dict, e.g. Catalogue.test_inputs' stored
// definition; it starts with '{', which no preset name does), a preset name
// or a JSON file's path.
engine::ArrayGeometry ResolveArray(const std::string& array, const std::filesystem::path& presets) {
  if (array.starts_with('{')) {
    const std::string source = "the array definition given to napkin.transform";
    const nlohmann::json json = nlohmann::json::parse(array, nullptr, /*allow_exceptions=*/false);
    if (json.is_discarded()) throw InputError(source + " is not valid JSON.");
    return formats::ParseArrayJson(json, source);
  }
  return ReadOnce(formats::ResolvePreset(array, "arrays", presets), formats::ReadArrayJson);
}

std::string SlotList(const engine::ArrayGeometry& array) {
  return Joined(array.sensors, [](const engine::Sensor& sensor) { return sensor.slot; });
}

// The samples (rows) of each of the array's slots (columns, the array's
// order) from a dict slot -> 1-D array or a 2-D array (samples, slots).
Eigen::MatrixXd ReadChannels(const py::handle& channels, const engine::ArrayGeometry& array,
                             const std::string& source) {
  const auto slot_count = static_cast<Eigen::Index>(array.sensors.size());
  if (py::isinstance<py::dict>(channels)) {
    const auto dict = py::reinterpret_borrow<py::dict>(channels);
    for (const auto& [key, unused] : dict) {
      if (!py::isinstance<py::str>(key))
        throw InputError(source + ": the channels dict has the key " + py::repr(key).cast<std::string>() +
                         "; its keys are slot names of array " + util::Quoted(array.name) + " (" +
                         SlotList(array) + ").");
      const auto slot = key.cast<std::string>();
      if (!array.FindSlot(slot))
        throw InputError(source + ": the channels name slot " + util::Quoted(slot) + ", which array " +
                         util::Quoted(array.name) + " does not have (its slots: " + SlotList(array) + ").");
    }
    Eigen::MatrixXd samples;
    std::string first_slot;
    for (Eigen::Index c = 0; c < slot_count; ++c) {
      const std::string& slot = array.sensors[static_cast<std::size_t>(c)].slot;
      if (!dict.contains(slot))
        throw InputError(source + ": no channel for slot " + util::Quoted(slot) + " of array " +
                         util::Quoted(array.name) + ".");
      const auto values = AsFloatArray(dict[py::str(slot)], source + ": channel " + util::Quoted(slot));
      if (values.ndim() != 1)
        throw InputError(source + ": channel " + util::Quoted(slot) + " has " +
                         std::to_string(values.ndim()) +
                         " dimensions; each channel is a 1-D array of samples.");
      const auto n = static_cast<Eigen::Index>(values.shape(0));
      if (c == 0) {
        samples.resize(n, slot_count);
        first_slot = slot;
      } else if (n != samples.rows()) {
        throw InputError(source + ": channel " + util::Quoted(slot) + " has " + std::to_string(n) +
                         " samples but channel " + util::Quoted(first_slot) + " has " +
                         std::to_string(samples.rows()) + ".");
      }
      samples.col(c) = Eigen::Map<const Eigen::VectorXd>(values.data(), n);
    }
    return samples;
  }
  const auto values = AsFloatArray(channels, source + ": channels (a dict slot -> array, or a 2-D array)");
  if (values.ndim() != 2 || values.shape(1) != slot_count) {
    std::string shape;
    for (py::ssize_t d = 0; d < values.ndim(); ++d)
      shape += (d > 0 ? ", " : "") + std::to_string(values.shape(d));
    throw InputError(source + ": channels is an array of shape (" + shape +
                     "); as an array it is 2-D, one row per sample and one column per slot of array " +
                     util::Quoted(array.name) + " in its order (" + std::to_string(slot_count) +
                     " columns: " + SlotList(array) + ").");
  }
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  return Eigen::Map<const RowMajor>(values.data(), values.shape(0), values.shape(1));
}

// t0 and dt from time_s (checked as the CSV reader checks its time column) or dt.
formats::TimeBase ReadTimeBase(const py::object& time_s, const py::object& dt, Eigen::Index samples,
                               const std::string& source) {
  if (time_s.is_none() == dt.is_none())
    throw InputError(source + ": give either time_s (the sample times, s) or dt (the sampling interval, s)" +
                     (time_s.is_none() ? std::string(", neither was given.") : ", not both."));
  if (!dt.is_none()) {
    const double step = dt.cast<double>();
    if (!(std::isfinite(step) && step > 0.0))
      throw InputError(source + ": dt " + util::FormatNumber(step) +
                       " s is not a finite positive sampling interval.");
    return {0.0, step};
  }
  const auto times = AsFloatArray(time_s, source + ": time_s");
  if (times.ndim() != 1 || times.shape(0) != samples)
    throw InputError(source + ": time_s has " +
                     std::to_string(times.ndim() == 1 ? times.shape(0) : times.size()) +
                     " values but the channels have " + std::to_string(samples) + " samples.");
  const std::span<const double> values(times.data(), static_cast<std::size_t>(times.shape(0)));
  for (std::size_t k = 0; k < values.size(); ++k)
    if (!std::isfinite(values[k]))
      throw InputError(source + ": time_s[" + std::to_string(k) + "] is " + util::FormatNumber(values[k]) +
                       ", not a finite number.");
  return formats::UniformTimeBase(
      values, source, [](std::size_t k) { return "time_s[" + std::to_string(k) + "]"; }, "sample");
}

Eigen::Vector3d Triple(const std::vector<double>& values, const char* name, const std::string& source) {
  if (values.size() != 3)
    throw InputError(source + ": " + name + " takes 3 numbers, not " + std::to_string(values.size()) + ".");
  for (const double value : values)
    if (!std::isfinite(value))
      throw InputError(source + ": " + name + " has a value that is not a finite number.");
  return {values[0], values[1], values[2]};
}

// (summary JSON text, {derived channel name: array}); napkin/__init__.py
// makes the TransformResult.
py::tuple Transform(const py::object& channels, const py::object& time_s, const py::object& dt,
                    const std::string& array_name, const std::string& config_name,
                    const std::vector<double>& orientation_rad,
                    const std::vector<double>& initial_velocity_mps,
                    const std::vector<double>& initial_omega_body_radps,
                    const std::optional<std::string>& solver, const std::string& test_id,
                    const std::string& config_dir) {
  const std::string source = Source(test_id);
  const std::filesystem::path presets =
      config_dir.empty() ? formats::DefaultConfigDir() : std::filesystem::path(config_dir);
  const engine::ArrayGeometry array = ResolveArray(array_name, presets);
  engine::ProcessingConfig config =
      ReadOnce(records::ProcessingConfigPath(config_name, presets), formats::ReadProcessingConfig);
  if (solver) {
    const std::optional<engine::SolverKind> kind = engine::ParseName<engine::SolverKind>(*solver);
    if (!kind)
      throw InputError(
          source + ": unknown solver " + util::Quoted(*solver) + " (use " +
          Joined(engine::kSolverKinds, [](engine::SolverKind k) { return std::string(engine::NameOf(k)); }) +
          ").");
    config.solver = *kind;
    config.Check();
  }
  engine::TestSignals signals;
  signals.samples = ReadChannels(channels, array, source);
  // As the CSV reader refuses a cell that is no finite number (its row and column).
  for (Eigen::Index c = 0; c < signals.samples.cols(); ++c)
    for (Eigen::Index k = 0; k < signals.samples.rows(); ++k)
      if (!std::isfinite(signals.samples(k, c)))
        throw InputError(source + ": sample " + std::to_string(k) + ", channel " +
                         util::Quoted(array.sensors[static_cast<std::size_t>(c)].slot) + ": " +
                         util::Quoted(util::FormatNumber(signals.samples(k, c))) +
                         " is not a finite number.");
  if (signals.samples.rows() < 2)
    throw InputError(source + ": the channels have " + std::to_string(signals.samples.rows()) +
                     " samples, at least two are needed.");
  const formats::TimeBase time_base = ReadTimeBase(time_s, dt, signals.samples.rows(), source);
  signals.t0_s = time_base.t0_s;
  signals.dt_s = time_base.dt_s;
  for (const engine::Sensor& sensor : array.sensors) signals.slots.push_back(sensor.slot);
  engine::InitialState initial;
  initial.orientation_rad = Triple(orientation_rad, "orientation", source);
  initial.velocity_fixed_mps = Triple(initial_velocity_mps, "initial_velocity", source);
  initial.omega_body_radps = Triple(initial_omega_body_radps, "initial_omega_body", source);

  // A loop over tests reuses the memory freed by the previous one, as `napkin run` does.
  util::KeepFreedMemoryForReuse();
  engine::ProcessedTest processed;
  {
    const py::gil_scoped_release computing;
    try {
      processed = engine::ProcessTest(array, signals, initial, config);
      // A test that fails `napkin run` fails here, with the same sentence.
      if (const engine::Finding* failing = engine::FailingFinding(processed))
        throw InputError(failing->detail);
    } catch (const InputError& error) {
      throw InputError(source + ": " + error.what());
    }
  }
  const std::string summary_json =
      formats::SummaryToJson(processed.summary, test_id, "", "")
          .dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
  return py::make_tuple(summary_json, DerivedChannelsToNumpy(std::move(processed.kinematics)));
}

}  // namespace

void RegisterTransform(py::module_& module) {
  module.def(
      "transform",
      [](const py::object& channels, const py::object& time_s, const py::object& dt, const std::string& array,
         const std::string& config, const std::vector<double>& orientation,
         const std::vector<double>& initial_velocity, const std::vector<double>& initial_omega_body,
         const std::optional<std::string>& solver, const std::string& test_id,
         const std::string& config_dir) {
        return Translated("", [&] {
          return Transform(channels, time_s, dt, array, config, orientation, initial_velocity,
                           initial_omega_body, solver, test_id, config_dir);
        });
      },
      py::arg("channels"), py::arg("time_s"), py::arg("dt"), py::arg("array"), py::arg("config"),
      py::arg("orientation"), py::arg("initial_velocity"), py::arg("initial_omega_body"), py::arg("solver"),
      py::arg("test_id"), py::arg("config_dir"));
}

}  // namespace napkin::python
