#pragma once
// The pieces of the Python extension module `napkin._napkin` (python/): one
// Register function per part, and what they share. The module is a thin
// layer over the libraries `napkin` is built from, so a Python result is the
// CLI's result (docs/python.md).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <exception>
#include <string>
#include <utility>

#include "cli/diagnostics.h"
#include "engine/kinematics.h"

namespace napkin::python {

namespace py = pybind11;

void RegisterTransform(py::module_& module);
void RegisterCriteria(py::module_& module);
void RegisterCatalogue(py::module_& module);

// A numpy array that owns `values` (moved, not copied).
py::array_t<double> ToNumpy(Eigen::VectorXd values);

// The derived channels of `kinematics` (formats::DerivedChannelSources) as a
// dict column name -> numpy array in the CSV column's unit, without the
// channels the test does not have. The arrays are views into the kinematics,
// moved into one Python object they all keep alive and scaled there in place:
// no channel is copied.
py::dict DerivedChannelsToNumpy(engine::Kinematics kinematics);

// `object` as a contiguous float64 numpy array (a view when it already is
// one); throws ValueError naming it `what` when it is no array of numbers.
py::array_t<double, py::array::c_style | py::array::forcecast> AsFloatArray(const py::handle& object,
                                                                            const std::string& what);

// Runs `work`, turning a napkin exception into the Python exception with the
// CLI's sentence (cli/diagnostics.h DescribeFailure): bad input (InputError,
// UsageError) raises ValueError, anything else RuntimeError; `db_path` names
// the catalogue in database errors. Python's own exceptions pass unchanged.
template <typename Work>
auto Translated(const std::string& db_path, Work&& work) -> decltype(work()) {
  try {
    return work();
  } catch (const py::error_already_set&) {
    throw;
  } catch (const py::builtin_exception&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw;  // MemoryError
  } catch (...) {
    const cli::Failure failure = cli::DescribeFailure(std::current_exception(), db_path);
    if (failure.bad_input) throw py::value_error(failure.sentence);
    throw std::runtime_error(failure.sentence);  // RuntimeError
  }
}

}  // namespace napkin::python
