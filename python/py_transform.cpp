// napkin.transform: one test's raw signals from numpy arrays through the
// path `napkin transform` takes (app/transform.h: SignalsFromSamples, the CSV
// reader's checks, and ProcessSignals) to its summary JSON and derived
// channels (docs/python.md "transform"); napkin.transform_file: one test file
// of any input format, read as `napkin transform` reads it (app::ReadTestFile).
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "app/transform.h"
#include "common/error.h"
#include "common/joined.h"
#include "engine/cancellation.h"
#include "engine/pipeline.h"
#include "formats/array_json.h"
#include "formats/json_file.h"
#include "formats/processing_config_json.h"
#include "formats/summary_json.h"
#include "jobs/watched_call.h"
#include "python/py_bindings.h"
#include "records/config_record.h"
#include "util/available_memory.h"
#include "util/text.h"

namespace napkin::python {
namespace {

// What a bad-input sentence starts with: the test id when the caller gave one
// (as the CLI names the input file), else the function.
std::string Source(const std::string& test_id) { return test_id.empty() ? "napkin.transform" : test_id; }

// A preset or JSON file parsed once per content: a loop over thousands of
// tests must not parse and check the same array and config for each
// (bench/run_python.sh), but a file rewritten in place is read again however
// little time passed and whatever its size (a modification time has a coarse
// tick). The bytes are read every call (a few KiB) and compared with those
// the cached value was parsed from; a value is only cached when the file
// still holds the bytes it was parsed from. Called with the GIL held, which
// serialises the callers.
template <typename Value>
Value ReadOnce(const std::filesystem::path& path, Value (*read)(const std::filesystem::path&)) {
  struct Entry {
    std::string content;
    Value value;
  };
  static std::map<std::filesystem::path, Entry> cache;
  std::string content;
  try {
    content = formats::ReadWholeFile(path, formats::kMaxJsonFileBytes);
  } catch (const InputError&) {
    return read(path);  // read() says what is wrong with it, in its own words
  }
  std::error_code error;
  const std::filesystem::path key = std::filesystem::absolute(path, error);
  const auto found = cache.find(key);
  if (found != cache.end() && found->second.content == content) return found->second.value;
  Value value = read(path);
  std::string after;
  try {
    after = formats::ReadWholeFile(path, formats::kMaxJsonFileBytes);
  } catch (const InputError&) {
    return value;  // changed (or gone) while it was read: not cached
  }
  if (after != content) return value;
  return cache.insert_or_assign(key, Entry{std::move(content), std::move(value)}).first->second.value;
}

// An array or processing config as napkin.transform takes it: a dict (the
// JSON file's content, e.g. Catalogue.test_inputs' stored array definition),
// converted as it is (FromPython), or a preset name or file path.
using Definition = std::variant<nlohmann::json, std::string>;

Definition AsDefinition(const py::handle& object, const std::string& what) {
  if (py::isinstance<py::dict>(object)) return FromPython(object, what);
  return AsNameOrPath(object, what);
}

// The array `array` gives, read by the reader of array files.
engine::ArrayGeometry ResolveArray(const Definition& array, const std::filesystem::path& presets) {
  if (const auto* json = std::get_if<nlohmann::json>(&array))
    return formats::ParseArrayJson(*json, "the array definition given to napkin.transform");
  return ReadOnce(formats::ResolvePreset(formats::PresetKind::kArray, std::get<std::string>(array), presets),
                  formats::ReadArrayJson);
}

// The processing config `config` gives, read by the reader of config files.
engine::ProcessingConfig ResolveProcessingConfig(const Definition& config, const std::string& function,
                                                 const std::filesystem::path& presets) {
  if (const auto* json = std::get_if<nlohmann::json>(&config))
    return formats::ParseProcessingConfig(*json, "the processing config given to " + function);
  return ReadOnce(records::ProcessingConfigPath(std::get<std::string>(config), presets),
                  formats::ReadProcessingConfig);
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
      RaiseIfSignalled();
      samples.col(c) = Eigen::Map<const Eigen::VectorXd>(values.data(), n);
    }
    return samples;
  }
  const auto values = AsFloatArray(channels, source + ": channels (a dict slot -> array, or a 2-D array)");
  if (values.ndim() != 2 || values.shape(1) != slot_count) {
    // Appended: GCC 12's LTO build (the package) warned a false -Wstringop-overflow on a `+` here.
    std::string shape;
    for (py::ssize_t d = 0; d < values.ndim(); ++d)
      shape.append(d > 0 ? ", " : "").append(std::to_string(values.shape(d)));
    throw InputError(source + ": channels is an array of shape (" + shape +
                     "); as an array it is 2-D, one row per sample and one column per slot of array " +
                     util::Quoted(array.name) + " in its order (" + std::to_string(slot_count) +
                     " columns: " + SlotList(array) + ").");
  }
  // A column at a time, so that Ctrl-C is looked at between two.
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::Map<const RowMajor> rows(values.data(), values.shape(0), values.shape(1));
  Eigen::MatrixXd samples(rows.rows(), rows.cols());
  for (Eigen::Index c = 0; c < rows.cols(); ++c) {
    RaiseIfSignalled();
    samples.col(c) = rows.col(c);
  }
  return samples;
}

// The sample times: dt_s, or time_s as a 1-D array (app::SignalsFromSamples checks them).
struct Times {
  std::optional<py::array_t<double, py::array::c_style | py::array::forcecast>>
      time_s;  // keeps the span alive
  app::SampleTimes times;
};
Times ReadTimes(const py::object& time_s, const std::optional<double>& dt, const std::string& source) {
  if (time_s.is_none() == !dt)
    throw InputError(source +
                     ": give either time_s (the sample times, s) or dt_s (the sampling interval, s)" +
                     (time_s.is_none() ? std::string(", neither was given.") : ", not both."));
  if (dt) return {std::nullopt, *dt};
  Times times{AsFloatArray(time_s, source + ": time_s"), 0.0};
  if (times.time_s->ndim() != 1)
    throw InputError(source + ": time_s is an array of " + std::to_string(times.time_s->ndim()) +
                     " dimensions; it is a 1-D array, one time per sample.");
  times.times =
      std::span<const double>(times.time_s->data(), static_cast<std::size_t>(times.time_s->shape(0)));
  return times;
}

Eigen::Vector3d Triple(const std::vector<double>& values, const char* name, const std::string& source) {
  if (values.size() != 3)
    throw InputError(source + ": " + name + " takes 3 numbers, not " + std::to_string(values.size()) + ".");
  for (const double value : values)
    if (!std::isfinite(value))
      throw InputError(source + ": " + name + " has a value that is not a finite number.");
  return {values[0], values[1], values[2]};
}

// A complex number (Python's, or a numpy scalar of complex dtype): ReadTimes refuses a
// complex time_s, and float() of one would first warn (numpy's ComplexWarning) and drop
// its imaginary part.
bool IsComplex(const py::handle& value) {
  if (PyComplex_Check(value.ptr())) return true;
  if (!py::hasattr(value, "dtype")) return false;
  try {
    return py::str(value.attr("dtype").attr("kind")).cast<std::string>() == "c";
  } catch (const py::error_already_set&) {
    return false;
  }
}

// The sample count of `channels` (a dict slot -> 1-D array, or a 2-D array)
// without converting or copying anything, and the sampling interval from dt or
// time_s (0 when unknown): what the memory estimate needs before the samples
// are copied. 0 samples when it cannot tell (ReadChannels then says why).
std::pair<Eigen::Index, double> SizeOf(const py::handle& channels, const engine::ArrayGeometry& array,
                                       const std::optional<double>& dt, const py::handle& time_s) {
  py::array first;
  if (py::isinstance<py::dict>(channels)) {
    const auto dict = py::reinterpret_borrow<py::dict>(channels);
    for (const engine::Sensor& sensor : array.sensors)
      if (dict.contains(sensor.slot)) {
        first = py::array::ensure(dict[py::str(sensor.slot)]);
        break;
      }
  } else {
    first = py::array::ensure(channels);
  }
  PyErr_Clear();
  if (!first || first.ndim() < 1) return {0, 0.0};
  const auto samples = static_cast<Eigen::Index>(first.shape(0));
  double dt_s = dt.value_or(0.0);
  if (!dt && samples > 1) {
    try {
      const py::object first_time = time_s[py::int_(0)];
      const py::object last_time = time_s[py::int_(samples - 1)];
      if (IsComplex(first_time) || IsComplex(last_time)) return {samples, 0.0};
      const double t0 = py::float_(first_time).cast<double>();
      const double t1 = py::float_(last_time).cast<double>();
      dt_s = (t1 - t0) / static_cast<double>(samples - 1);
    } catch (const py::error_already_set&) {
      dt_s = 0.0;  // ReadTimes says what is wrong with it
    }
  }
  return {samples, std::isfinite(dt_s) && dt_s > 0.0 ? dt_s : 0.0};
}

// The memory a transform takes: this module's copy of the samples plus
// engine::ProcessTestBytes.
std::uint64_t TransformBytes(const engine::ArrayGeometry& array, Eigen::Index samples, double dt_s,
                             const engine::ProcessingConfig& config) {
  if (samples <= 0) return 0;
  const std::uint64_t copy = static_cast<std::uint64_t>(samples) * array.sensors.size() * sizeof(double);
  return copy + engine::ProcessTestBytes(array, samples, dt_s, config);
}

// Refuses, before anything is copied, a test whose processing cannot fit in
// the memory available (util/available_memory.h): a MemoryError in one
// sentence saying both, rather than std::bad_alloc minutes into the work (or
// the OOM killer).
void CheckMemory(const engine::ArrayGeometry& array, Eigen::Index samples, double dt_s,
                 const engine::ProcessingConfig& config, const std::string& source) {
  if (samples <= 0) return;
  const std::uint64_t needed = TransformBytes(array, samples, dt_s, config);
  if (const auto sentence = util::MemoryShortfall(source + ": processing " + std::to_string(samples) +
                                                      " samples of array " + util::Quoted(array.name),
                                                  needed, util::FindAvailableMemory())) {
    PyErr_SetString(PyExc_MemoryError, sentence->c_str());
    throw py::error_already_set();
  }
}

// Whether this is the interpreter's main thread, the one thread that runs
// Python's signal handlers (so the one that can see Ctrl-C).
bool OnMainThread() {
  const py::module_ threading = py::module_::import("threading");
  return threading.attr("main_thread")().is(threading.attr("current_thread")());
}

// How often the main thread looks for a signal while a test is computed.
constexpr std::chrono::milliseconds kSignalPollInterval{50};

py::tuple Computed(const engine::ArrayGeometry& array, const engine::TestSignals& signals,
                   const engine::InitialState& initial, const engine::ProcessingConfig& config,
                   const std::string& source, const std::string& test_id);

// (summary as a dict (ToPython), {derived channel name: array}); napkin/__init__.py
// makes the TransformResult. Arguments arrive as Python objects and are
// converted here, so that one of the wrong type raises TypeError naming it.
py::tuple Transform(const py::object& channels, const py::object& time_s, const py::object& dt_object,
                    const py::object& array_object, const py::object& config_object,
                    const py::object& orientation_object, const py::object& initial_velocity_object,
                    const py::object& initial_omega_body_object, const py::object& solver_object,
                    const py::object& test_id_object) {
  const std::string function = "napkin.transform: ";
  const std::string test_id = AsText(test_id_object, function + "test_id", "a test id");
  const std::optional<double> dt = AsOptionalReal(dt_object, function + "dt_s", "the sampling interval in s");
  const Definition array_definition = AsDefinition(array_object, function + "array");
  const Definition config_definition = AsDefinition(config_object, function + "config");
  const std::vector<double> orientation_rad =
      AsReals(orientation_object, function + "orientation_rad", "phi, theta, psi in rad");
  const std::vector<double> initial_velocity_mps =
      AsReals(initial_velocity_object, function + "initial_velocity_mps", "3 components in m/s");
  const std::vector<double> initial_omega_body_radps =
      AsReals(initial_omega_body_object, function + "initial_omega_body_radps", "3 components in rad/s");
  std::optional<std::string> solver;
  if (!solver_object.is_none()) solver = AsText(solver_object, function + "solver", "a solver name or None");

  const std::string source = Source(test_id);
  const std::filesystem::path presets = formats::DefaultConfigDir();
  const engine::ArrayGeometry array = ResolveArray(array_definition, presets);
  engine::ProcessingConfig config = ResolveProcessingConfig(config_definition, "napkin.transform", presets);
  if (solver) app::SetSolver(config, *solver);
  const auto [samples, dt_estimate] = SizeOf(channels, array, dt, time_s);
  CheckMemory(array, samples, dt_estimate, config, source);

  Eigen::MatrixXd values = ReadChannels(channels, array, source);
  const Times times = ReadTimes(time_s, dt, source);
  const engine::TestSignals signals = app::SignalsFromSamples(std::move(values), array, times.times, source);
  engine::InitialState initial;
  initial.orientation_rad = Triple(orientation_rad, "orientation_rad", source);
  initial.velocity_fixed_mps = Triple(initial_velocity_mps, "initial_velocity_mps", source);
  initial.omega_body_radps = Triple(initial_omega_body_radps, "initial_omega_body_radps", source);
  return Computed(array, signals, initial, config, source, test_id);
}

// napkin.transform_file: one test file of any input format read as `napkin transform` reads it
// (app::ReadTestFile) and processed as transform processes samples; (summary dict, derived
// channels, warnings).
py::tuple TransformFile(const py::object& path_object, const py::object& array_object,
                        const py::object& channel_map_object, const py::object& position_object,
                        const py::object& columns_object, const py::object& config_object,
                        const py::object& orientation_object, const py::object& initial_velocity_object,
                        const py::object& solver_object) {
  const std::string function = "napkin.transform_file: ";
  app::TestFileOptions read;
  read.path = AsNameOrPath(path_object, function + "path");
  if (!array_object.is_none()) read.array = AsNameOrPath(array_object, function + "array");
  if (!channel_map_object.is_none())
    read.channel_map = AsNameOrPath(channel_map_object, function + "channel_map");
  if (!position_object.is_none())
    read.position = AsText(position_object, function + "position", "a position such as \"11\", or None");
  if (!columns_object.is_none()) {
    if (!py::isinstance<py::dict>(columns_object))
      throw py::type_error(function + "columns is " + Described(columns_object) +
                           "; it is a dict slot -> CSV column name, or None.");
    for (const auto& [slot, column] : py::reinterpret_borrow<py::dict>(columns_object))
      read.csv_columns.push_back(AsText(slot, function + "columns", "a slot name") + "=" +
                                 AsText(column,
                                        function + "columns[" + py::repr(slot).cast<std::string>() + "]",
                                        "a CSV column name"));
  }
  read.array_option = "array=";
  const Definition config_definition = AsDefinition(config_object, function + "config");
  const std::vector<double> orientation_rad =
      AsReals(orientation_object, function + "orientation_rad", "phi, theta, psi in rad");
  const std::vector<double> initial_velocity_mps =
      AsReals(initial_velocity_object, function + "initial_velocity_mps", "3 components in m/s");
  std::optional<std::string> solver;
  if (!solver_object.is_none()) solver = AsText(solver_object, function + "solver", "a solver name or None");

  const std::filesystem::path presets = formats::DefaultConfigDir();
  read.config_dir = presets;
  engine::ProcessingConfig config =
      ResolveProcessingConfig(config_definition, "napkin.transform_file", presets);
  if (solver) app::SetSolver(config, *solver);
  const app::TestFile file = app::ReadTestFile(read);
  CheckMemory(file.array, file.signals.size(), file.signals.dt_s, config, read.path);
  engine::InitialState initial;
  initial.orientation_rad = Triple(orientation_rad, "orientation_rad", read.path);
  initial.velocity_fixed_mps = Triple(initial_velocity_mps, "initial_velocity_mps", read.path);
  const py::tuple computed = Computed(file.array, file.signals, initial, config, read.path, file.test_id);
  py::list warnings;
  for (const std::string& warning : file.warnings) warnings.append(warning);
  return py::make_tuple(computed[0], computed[1], warnings);
}

// One test's signals processed as `napkin transform` processes them (app::ProcessSignals), Ctrl-C
// stopping the computation: (summary dict, {derived channel name: array}).
py::tuple Computed(const engine::ArrayGeometry& array, const engine::TestSignals& signals,
                   const engine::InitialState& initial, const engine::ProcessingConfig& config,
                   const std::string& source, const std::string& test_id) {
  // A loop over tests works in the memory of the one before, without tuning
  // the host's malloc (docs/python.md "Cost"): the calling thread's
  // workspace, and the series of a result Python has let go.
  thread_local engine::Workspace workspace;
  engine::ProcessedTest processed;
  processed.kinematics = TakeSpareKinematics();
  const auto compute = [&](const std::atomic<bool>* cancel) {
    app::ProcessSignals(array, signals, initial, config, source, workspace, processed, cancel);
  };
  // Ctrl-C: Python's handler only notes the signal, and only the main
  // thread runs the Python-level handler (KeyboardInterrupt), when it calls
  // PyErr_CheckSignals. So on the main thread the test is computed on a
  // thread of its own while this one checks for signals every 50 ms, and a
  // signal whose handler raises stops the computation (engine::Cancelled)
  // and raises here. Elsewhere Ctrl-C is the main thread's business, as for
  // any Python code: compute in place.
  bool interrupted = false;
  const bool watch = OnMainThread();
  RaiseIfSignalled();  // Ctrl-C while the channels were read: no need to start
  {
    const py::gil_scoped_release computing;
    try {
      if (watch) {
        jobs::RunWatched([&](const std::atomic<bool>& cancel) { compute(&cancel); },
                         [&] {
                           const py::gil_scoped_acquire checking;
                           interrupted = PyErr_CheckSignals() != 0;
                           return interrupted;
                         },
                         kSignalPollInterval);
      } else {
        compute(nullptr);
      }
    } catch (const engine::Cancelled&) {
      if (!interrupted) throw;
    } catch (const InputError&) {
      if (!interrupted) throw;  // app::ProcessSignals' sentence, naming the source
    }
  }
  // The handler's exception (KeyboardInterrupt) is set: raise it, whether or
  // not the computation ended first.
  if (interrupted) throw py::error_already_set();
  const py::object summary = ToPython(formats::SummaryToJson(processed.summary, test_id, "", ""));
  RaiseIfSignalled();
  return py::make_tuple(summary, DerivedChannelsToNumpy(std::move(processed.kinematics)));
}

}  // namespace

void RegisterTransform(py::module_& module) {
  module.def(
      "transform",
      [](const py::object& channels, const py::object& time_s, const py::object& dt, const py::object& array,
         const py::object& config, const py::object& orientation, const py::object& initial_velocity,
         const py::object& initial_omega_body, const py::object& solver, const py::object& test_id) {
        return Translated("", [&] {
          return Transform(channels, time_s, dt, array, config, orientation, initial_velocity,
                           initial_omega_body, solver, test_id);
        });
      },
      py::arg("channels"), py::arg("time_s"), py::arg("dt_s"), py::arg("array"), py::arg("config"),
      py::arg("orientation_rad"), py::arg("initial_velocity_mps"), py::arg("initial_omega_body_radps"),
      py::arg("solver"), py::arg("test_id"));
  module.def(
      "transform_file",
      [](const py::object& path, const py::object& array, const py::object& channel_map,
         const py::object& position, const py::object& columns, const py::object& config,
         const py::object& orientation, const py::object& initial_velocity, const py::object& solver) {
        return Translated("", [&] {
          return TransformFile(path, array, channel_map, position, columns, config, orientation,
                               initial_velocity, solver);
        });
      },
      py::arg("path"), py::arg("array"), py::arg("channel_map"), py::arg("position"), py::arg("columns"),
      py::arg("config"), py::arg("orientation_rad"), py::arg("initial_velocity_mps"), py::arg("solver"));
  // The estimate CheckMemory compares with the memory available, for the
  // tests that hold it to a transform's measured peak (python/tests/).
  module.def(
      "_transform_bytes",
      [](const std::string& array_name, Eigen::Index samples, double dt_s, const std::string& config_name,
         const std::string& config_dir) {
        return Translated("", [&] {
          const std::filesystem::path presets =
              config_dir.empty() ? formats::DefaultConfigDir() : std::filesystem::path(config_dir);
          return TransformBytes(
              formats::ReadArrayJson(
                  formats::ResolvePreset(formats::PresetKind::kArray, array_name, presets)),
              samples, dt_s,
              formats::ReadProcessingConfig(records::ProcessingConfigPath(config_name, presets)));
        });
      },
      py::arg("array"), py::arg("samples"), py::arg("dt_s"), py::arg("config") = "default",
      py::arg("config_dir") = "");
}

}  // namespace napkin::python
