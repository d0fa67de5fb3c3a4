// `napkin._napkin`, the compiled half of the Python package `napkin`
// (python/napkin/__init__.py is the other; docs/python.md).
#include <memory>
#include <span>
#include <vector>

#include "common/version.h"
#include "formats/csv.h"
#include "python/py_bindings.h"

namespace napkin::python {

py::array_t<double> ToNumpy(Eigen::VectorXd values) {
  auto* owned = new Eigen::VectorXd(std::move(values));
  const py::capsule owner(owned, [](void* pointer) { delete static_cast<Eigen::VectorXd*>(pointer); });
  return py::array_t<double>({static_cast<py::ssize_t>(owned->size())},
                             {static_cast<py::ssize_t>(sizeof(double))}, owned->data(), owner);
}

py::dict DerivedChannelsToNumpy(engine::Kinematics kinematics) {
  auto owned = std::make_unique<engine::Kinematics>(std::move(kinematics));
  const std::vector<formats::DerivedChannelSource> sources = formats::DerivedChannelSources(*owned);
  const py::capsule owner(owned.get(),
                          [](void* pointer) { delete static_cast<engine::Kinematics*>(pointer); });
  static_cast<void>(owned.release());  // the capsule deletes it now
  py::dict channels;
  for (const formats::DerivedChannelSource& source : sources) {
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
  FloatArray array = FloatArray::ensure(object);
  if (!array) {
    PyErr_Clear();
    throw py::value_error(what + " is not an array of numbers.");
  }
  return array;
}

}  // namespace napkin::python

PYBIND11_MODULE(_napkin, module) {
  module.doc() = "napkin's engine and catalogue from Python (docs/python.md)";
  module.attr("__version__") = napkin::Version();
  napkin::python::RegisterTransform(module);
  napkin::python::RegisterCriteria(module);
  napkin::python::RegisterCatalogue(module);
}
