// `napkin._napkin`, the compiled half of the Python package `napkin`
// (python/napkin/__init__.py is the other; docs/python.md).
#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "common/error.h"
#include "common/version.h"
#include "formats/csv.h"
#include "python/py_bindings.h"
#include "util/malloc_tuning.h"

namespace napkin::python {

py::array_t<double> ToNumpy(Eigen::VectorXd values) {
  auto* owned = new Eigen::VectorXd(std::move(values));
  const py::capsule owner(owned, [](void* pointer) { delete static_cast<Eigen::VectorXd*>(pointer); });
  return py::array_t<double>({static_cast<py::ssize_t>(owned->size())},
                             {static_cast<py::ssize_t>(sizeof(double))}, owned->data(), owner);
}

namespace {

// Kinematics whose arrays were released, guarded by the GIL (the capsule's
// destructor and TakeSpareKinematics run with it held).
std::vector<std::unique_ptr<engine::Kinematics>>& SpareKinematics() {
  static auto* spares = new std::vector<std::unique_ptr<engine::Kinematics>>();  // never destroyed
  return *spares;
}

}  // namespace

engine::Kinematics TakeSpareKinematics() {
  auto& spares = SpareKinematics();
  if (spares.empty()) return {};
  engine::Kinematics kinematics = std::move(*spares.back());
  spares.pop_back();
  return kinematics;
}

py::dict DerivedChannelsToNumpy(engine::Kinematics kinematics) {
  auto owned = std::make_unique<engine::Kinematics>(std::move(kinematics));
  const std::vector<formats::DerivedChannelSource> sources = formats::DerivedChannelSources(*owned);
  const py::capsule owner(owned.get(), [](void* pointer) {
    std::unique_ptr<engine::Kinematics> released(static_cast<engine::Kinematics*>(pointer));
    constexpr std::size_t kKeptSpares = 2;  // a result still held while the next is computed
    if (SpareKinematics().size() < kKeptSpares) SpareKinematics().push_back(std::move(released));
  });
  static_cast<void>(owned.release());  // the capsule deletes it now
  py::dict channels;
  for (const formats::DerivedChannelSource& source : sources) {
    RaiseIfSignalled();
    if (source.values_si.empty()) continue;
    // The spans point into the kinematics this function owns (not const):
    // scaling through them scales its columns (acc to g, angles to degrees),
    // as DerivedChannels does on a copy.
    const std::span<double> values(const_cast<double*>(source.values_si.data()), source.values_si.size());
    if (source.to_csv_unit != 1.0)
      for (double& value : values) value *= source.to_csv_unit;
    channels[py::str(source.name.data(), source.name.size())] =
        py::array_t<double>({static_cast<py::ssize_t>(values.size())},
                            {static_cast<py::ssize_t>(sizeof(double))}, values.data(), owner);
  }
  return channels;
}

py::array_t<double, py::array::c_style | py::array::forcecast> AsFloatArray(const py::handle& object,
                                                                            const std::string& what) {
  using FloatArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
  // Its own dtype first (no conversion): numpy's cast to float64 would drop
  // an imaginary part (with a warning only) and parse text.
  const py::array as_given = py::array::ensure(object);
  if (!as_given) {
    PyErr_Clear();
    throw py::type_error(what + " is not an array of numbers.");
  }
  const char kind = as_given.dtype().kind();
  if (kind == 'c')
    throw py::type_error(what +
                         " holds complex numbers; napkin takes real samples (pass .real if the "
                         "imaginary part is to be dropped).");
  if (kind != 'i' && kind != 'u' && kind != 'f' && kind != 'O')
    throw py::type_error(what + " is not an array of numbers (its elements are of numpy dtype " +
                         py::str(as_given.dtype()).cast<std::string>() + ").");
  FloatArray array = FloatArray::ensure(as_given);
  if (!array) {
    PyErr_Clear();
    throw py::type_error(what + " is not an array of numbers.");
  }
  return array;
}

std::string Described(const py::handle& object) {
  std::string text = py::repr(object).cast<std::string>();
  if (text.size() > 60) text = text.substr(0, 57) + "...";
  const std::string type = py::str(py::type::handle_of(object).attr("__name__")).cast<std::string>();
  const bool vowel =
      !type.empty() && std::string_view("aeiouAEIOU").find(type.front()) != std::string_view::npos;
  return text + " (" + (vowel ? "an " : "a ") + type + ")";
}

namespace {

std::string Meaning(const std::string& meaning) { return meaning.empty() ? "" : " (" + meaning + ")"; }

bool IsReal(const py::handle& object) {
  if (PyBool_Check(object.ptr())) return false;
  if (py::isinstance(object, py::module_::import("numbers").attr("Real"))) return true;
  if (py::isinstance<py::array>(object)) {  // a 0-d array of a real kind
    const auto array = py::reinterpret_borrow<py::array>(object);
    const char kind = array.dtype().kind();
    return array.ndim() == 0 && (kind == 'i' || kind == 'u' || kind == 'f');
  }
  return false;
}

}  // namespace

double AsReal(const py::handle& object, const std::string& what, const std::string& meaning) {
  if (!IsReal(object))
    throw py::type_error(what + " is " + Described(object) + ", not a number" + Meaning(meaning) + ".");
  return py::float_(py::reinterpret_borrow<py::object>(object)).cast<double>();
}

std::optional<double> AsOptionalReal(const py::handle& object, const std::string& what,
                                     const std::string& meaning) {
  if (object.is_none()) return std::nullopt;
  return AsReal(object, what, meaning);
}

std::vector<double> AsReals(const py::handle& object, const std::string& what, const std::string& meaning) {
  const bool sequence =
      (py::isinstance<py::sequence>(object) && !py::isinstance<py::str>(object) &&
       !py::isinstance<py::bytes>(object)) ||
      (py::isinstance<py::array>(object) && py::reinterpret_borrow<py::array>(object).ndim() == 1);
  if (!sequence)
    throw py::type_error(what + " is " + Described(object) + ", not a sequence of numbers" +
                         Meaning(meaning) + ".");
  std::vector<double> values;
  for (const py::handle item : py::iter(object)) {
    if (!IsReal(item))
      throw py::type_error(what + " holds " + Described(item) + ", which is not a number" + Meaning(meaning) +
                           ".");
    values.push_back(AsReal(item, what, meaning));
  }
  return values;
}

std::string AsText(const py::handle& object, const std::string& what, const std::string& expected) {
  if (!py::isinstance<py::str>(object))
    throw py::type_error(what + " is " + Described(object) + ", not " + expected + " (a str).");
  return object.cast<std::string>();
}

std::string AsNameOrPath(const py::handle& object, const std::string& what) {
  if (py::isinstance<py::str>(object)) return object.cast<std::string>();
  if (py::hasattr(object, "__fspath__")) {
    const py::object path = py::module_::import("os").attr("fsdecode")(object);
    if (py::isinstance<py::str>(path)) return path.cast<std::string>();
  }
  throw py::type_error(what + " is " + Described(object) +
                       ", not a preset name or a file path (a str or a "
                       "pathlib.Path).");
}

namespace {

// Text as the CLI writes it: bytes that are not UTF-8 as U+FFFD.
py::str DecodedText(const std::string& text) {
  PyObject* decoded = PyUnicode_DecodeUTF8(text.data(), static_cast<Py_ssize_t>(text.size()), "replace");
  if (decoded == nullptr) throw py::error_already_set();
  return py::reinterpret_steal<py::str>(decoded);
}

}  // namespace

py::object ToPython(const nlohmann::ordered_json& value) {
  switch (value.type()) {
    case nlohmann::ordered_json::value_t::object: {
      py::dict object;
      for (const auto& [key, member] : value.items()) object[DecodedText(key)] = ToPython(member);
      return object;
    }
    case nlohmann::ordered_json::value_t::array: {
      py::list list;
      for (const auto& element : value) list.append(ToPython(element));
      return list;
    }
    case nlohmann::ordered_json::value_t::string:
      return DecodedText(value.get_ref<const std::string&>());
    case nlohmann::ordered_json::value_t::boolean:
      return py::bool_(value.get<bool>());
    case nlohmann::ordered_json::value_t::number_integer:
      return py::int_(value.get<std::int64_t>());
    case nlohmann::ordered_json::value_t::number_unsigned:
      return py::int_(value.get<std::uint64_t>());
    case nlohmann::ordered_json::value_t::number_float: {
      const double number = value.get<double>();
      if (!std::isfinite(number)) return py::none();
      return py::float_(number);
    }
    default:
      return py::none();
  }
}

nlohmann::json FromPython(const py::handle& object, const std::string& what) {
  if (object.is_none()) return nullptr;
  if (py::isinstance<py::bool_>(object)) return object.cast<bool>();
  if (py::isinstance<py::int_>(object)) {
    int overflow = 0;
    const long long number = PyLong_AsLongLongAndOverflow(object.ptr(), &overflow);
    if (overflow != 0)
      throw InputError(what + " holds the integer " + py::repr(object).cast<std::string>() +
                       ", beyond the 64-bit integers napkin reads.");
    return static_cast<std::int64_t>(number);
  }
  if (py::isinstance<py::float_>(object)) {
    const double number = object.cast<double>();
    if (!std::isfinite(number))
      throw InputError(what + " holds " + py::repr(object).cast<std::string>() +
                       ", which is not a JSON number.");
    return number;
  }
  if (py::isinstance<py::str>(object)) return object.cast<std::string>();
  if (py::isinstance<py::dict>(object)) {
    nlohmann::json json = nlohmann::json::object();
    for (const auto& [key, member] : py::reinterpret_borrow<py::dict>(object)) {
      if (!py::isinstance<py::str>(key))
        throw py::type_error(what + " has the key " + py::repr(key).cast<std::string>() +
                             "; the keys of a definition are str, as in its JSON file.");
      const std::string name = key.cast<std::string>();
      json[name] = FromPython(member, what + "[" + py::repr(key).cast<std::string>() + "]");
    }
    return json;
  }
  if (py::isinstance<py::list>(object) || py::isinstance<py::tuple>(object)) {
    nlohmann::json json = nlohmann::json::array();
    std::size_t index = 0;
    for (const py::handle element : object)
      json.push_back(FromPython(element, what + "[" + std::to_string(index++) + "]"));
    return json;
  }
  throw py::type_error(what + " is " + Described(object) +
                       ", which a JSON file cannot hold (a definition holds dicts, lists, str, numbers, "
                       "bool and None).");
}

}  // namespace napkin::python

PYBIND11_MODULE(_napkin, module) {
  module.doc() = "napkin's engine and catalogue from Python (docs/python.md)";
  module.attr("__version__") = napkin::Version();
  napkin::python::RegisterErrors(module);
  napkin::python::RegisterTransform(module);
  napkin::python::RegisterCriteria(module);
  napkin::python::RegisterCatalogue(module);
  napkin::python::RegisterLimits(module);
  module.def(
      "tune_memory", [] { return napkin::util::KeepFreedMemoryForReuse(); },
      "Raises glibc's malloc thresholds for the whole process, as `napkin run` does (docs/python.md "
      "\"Cost\"): freed memory is kept for reuse instead of handed back to the kernel. Never called "
      "implicitly; napkin's own loops do not need it. Returns whether it was applied.");
}
