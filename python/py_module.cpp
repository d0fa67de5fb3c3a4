// `napkin._napkin`, the compiled half of the Python package `napkin`
// (python/napkin/__init__.py is the other; docs/python.md).
#include "common/version.h"
#include "python/py_bindings.h"

namespace napkin::python {

py::array_t<double> ToNumpy(Eigen::VectorXd values) {
  auto* owned = new Eigen::VectorXd(std::move(values));
  const py::capsule owner(owned, [](void* pointer) { delete static_cast<Eigen::VectorXd*>(pointer); });
  return py::array_t<double>({static_cast<py::ssize_t>(owned->size())},
                             {static_cast<py::ssize_t>(sizeof(double))}, owned->data(), owner);
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
