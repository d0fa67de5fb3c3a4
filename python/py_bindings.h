#pragma once
// The pieces of the Python extension module `napkin._napkin` (python/): one
// Register function per part, and what they share. The module is a thin
// layer over the libraries `napkin` is built from, so a Python result is the
// CLI's result (docs/python.md).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <exception>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "app/failure.h"
#include "engine/kinematics.h"

namespace napkin::python {

namespace py = pybind11;

void RegisterTransform(py::module_& module);
void RegisterCriteria(py::module_& module);
void RegisterCatalogue(py::module_& module);
void RegisterLimits(py::module_& module);

// A numpy array that owns `values` (moved, not copied).
py::array_t<double> ToNumpy(Eigen::VectorXd values);

// The derived channels of `kinematics` (formats::DerivedChannelSources) as a
// dict column name -> numpy array in the CSV column's unit, without the
// channels the test does not have. The arrays are views into the kinematics,
// moved into one Python object they all keep alive and scaled there in place:
// no channel is copied. Ctrl-C between two channels raises (RaiseIfSignalled).
py::dict DerivedChannelsToNumpy(engine::Kinematics kinematics);

// Ctrl-C while this thread holds the GIL in a long conversion (a long
// record's channels into or out of numpy): Python's C-level handler has only
// noted the signal, and its Python-level handler would run once the call has
// returned. Runs the handlers now (on the main thread; elsewhere a no-op) and
// raises what one raised (KeyboardInterrupt), so that Ctrl-C stops a transform
// within the promised half second in every stage (docs/python.md).
inline void RaiseIfSignalled() {
  if (PyErr_CheckSignals() != 0) throw py::error_already_set();
}

// Kinematics whose arrays Python has let go (DerivedChannelsToNumpy keeps
// up to two), for the next transform to solve into: its memory is mapped
// already. Empty kinematics when there are none. Call with the GIL held
// (it guards the spares).
engine::Kinematics TakeSpareKinematics();

// `object` as a contiguous float64 numpy array (a view when it already is
// one) of real numbers (integers or floats: numpy's kinds i, u, f, or objects
// that are such numbers). Throws TypeError naming it `what` otherwise: for
// complex numbers (never cut to their real part), text (never parsed),
// booleans, dates, and what is no array of numbers at all.
py::array_t<double, py::array::c_style | py::array::forcecast> AsFloatArray(const py::handle& object,
                                                                            const std::string& what);

// Arguments of the wrong type raise TypeError with a sentence that names the
// argument (`what`, e.g. "napkin.transform: dt") and says what it got and what
// it takes: "napkin.transform: dt is '0.0001' (a str), not a number (the
// sampling interval in s)." `meaning` (may be empty) is that parenthesis.

// What `object` is, for such a sentence: its repr (abbreviated) and type.
std::string Described(const py::handle& object);

// A real number: int, float, numpy's integer and floating scalars (and 0-d
// arrays of them); not bool, str or complex.
double AsReal(const py::handle& object, const std::string& what, const std::string& meaning = "");

// None or a real number.
std::optional<double> AsOptionalReal(const py::handle& object, const std::string& what,
                                     const std::string& meaning = "");

// A sequence (list, tuple, 1-D array) of real numbers.
std::vector<double> AsReals(const py::handle& object, const std::string& what,
                            const std::string& meaning = "");

// A str (`expected` says what it names, e.g. "a solver name").
std::string AsText(const py::handle& object, const std::string& what, const std::string& expected);

// A str or an os.PathLike (pathlib.Path): a preset name or a file path.
std::string AsNameOrPath(const py::handle& object, const std::string& what);

// The JSON documents of the libraries (a transform's summary, a stored array
// definition) as the objects json.loads would make of their text: dicts in
// key order, lists, str (bytes not UTF-8 as U+FFFD, as the CLI writes them),
// int, float, bool, None (a non-finite number as None, as the CLI writes
// null). Converted directly: no JSON text passes between the application
// library and the module.
py::object ToPython(const nlohmann::ordered_json& value);
// A Python dict (str keys), list or tuple, str, int, float, bool or None as
// a JSON value: a definition given as a dict (napkin.transform's array and
// config). TypeError naming `what` for another type or a key that is not a
// str; InputError for NaN or infinity, which a JSON file cannot hold either.
nlohmann::json FromPython(const py::handle& object, const std::string& what);

// napkin's exception classes (napkin.Error and those derived from it) and
// napkin.Finding, created in the module: RegisterErrors.
void RegisterErrors(py::module_& module);

// Raises the Python exception of `failure`: the one place that maps a
// failure's category (app/failure.h) to an exception class
// (docs/python.md "Errors"):
//   kUsage, kInput           napkin.InputError (a ValueError)
//   kScreening               napkin.ScreeningFailure (an InputError) with .findings
//   kNotFound                napkin.NotFoundError (a CatalogueError and an InputError)
//   kCatalogueBusy, kCatalogue  napkin.CatalogueError (a RuntimeError)
//   kOutOfMemory             MemoryError
//   kInternal                napkin.InternalError (a RuntimeError)
[[noreturn]] void RaiseFailure(const app::Failure& failure);

// napkin.CatalogueError with `sentence` (a closed catalogue, python/py_catalogue.cpp).
[[noreturn]] void RaiseCatalogueError(const std::string& sentence);

// Runs `work`, turning a napkin exception into the Python exception with the
// CLI's sentence (app/failure.h DescribeFailure, RaiseFailure); `db_path`
// names the catalogue in database errors. Python's own exceptions pass
// unchanged.
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
    RaiseFailure(app::DescribeFailure(std::current_exception(), db_path));
  }
}

}  // namespace napkin::python
