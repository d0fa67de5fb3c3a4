// napkin's exceptions (docs/python.md "Errors"): the classes, created here so
// that the compiled module raises them, and the one mapping of a failure's
// category (app/failure.h) to a class.
#include <string>

#include "engine/vocabulary.h"
#include "python/py_bindings.h"

namespace napkin::python {
namespace {

// The classes, created once by RegisterErrors and kept for the life of the
// process (the module is never unloaded).
struct ErrorClasses {
  PyObject* input = nullptr;
  PyObject* screening = nullptr;
  PyObject* catalogue = nullptr;
  PyObject* not_found = nullptr;
  PyObject* internal = nullptr;
  PyObject* finding = nullptr;  // the named tuple napkin.Finding
};

ErrorClasses& Classes() {
  static ErrorClasses classes;
  return classes;
}

// A new exception class napkin.<name> derived from `bases`, set as the
// module's attribute `name`; `attributes` holds its class attributes.
PyObject* NewError(py::module_& module, const char* name, const char* doc, const py::tuple& bases,
                   const py::dict& attributes = py::dict()) {
  const std::string qualified = std::string("napkin.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), attributes.ptr());
  if (type == nullptr) throw py::error_already_set();
  module.add_object(name, py::reinterpret_borrow<py::object>(type));
  return type;  // the reference PyErr_NewExceptionWithDoc returned: kept
}

[[noreturn]] void Raise(PyObject* type, const std::string& sentence) {
  PyErr_SetString(type, sentence.c_str());
  throw py::error_already_set();
}

py::object FindingTuple(const engine::Finding& finding) {
  const py::object channel = finding.channel ? py::object(py::str(*finding.channel)) : py::object(py::none());
  return py::reinterpret_borrow<py::object>(Classes().finding)(
      finding.check, channel, std::string(engine::NameOf(finding.severity)), finding.detail);
}

}  // namespace

void RegisterErrors(py::module_& module) {
  ErrorClasses& classes = Classes();
  const py::handle exception(PyExc_Exception), value_error(PyExc_ValueError),
      runtime_error(PyExc_RuntimeError);
  PyObject* error =
      NewError(module, "Error",
               "The base class of the errors napkin raises; each carries one sentence naming the input, "
               "option, test or catalogue at fault (the sentence the napkin command prints). An argument "
               "of the wrong type raises TypeError instead, a test that cannot fit in memory MemoryError, "
               "Ctrl-C KeyboardInterrupt.",
               py::make_tuple(exception));
  classes.input = NewError(module, "InputError",
                           "Bad input the caller can correct: an unknown preset, slot or query field, a "
                           "malformed filter, samples that are not finite or not uniformly spaced. Also a "
                           "ValueError, as napkin raised before.",
                           py::make_tuple(py::handle(error), value_error));
  py::dict screening_attributes;
  screening_attributes["findings"] = py::list();
  classes.screening =
      NewError(module, "ScreeningFailure",
               "A test that fails napkin's screening (a saturated, flipped or implausible channel): the "
               "sentence `napkin transform` exits 1 with. .findings is the list of what screening found, "
               "the failing finding among them, each a napkin.Finding(check, channel, severity, detail).",
               py::make_tuple(py::handle(classes.input)), screening_attributes);
  classes.catalogue =
      NewError(module, "CatalogueError",
               "A catalogue problem: one that is busy (locked by a writer), damaged, or not a catalogue; "
               "one that is closed; and (NotFoundError) a catalogue or test that is not there. Also a "
               "RuntimeError, as napkin raised before.",
               py::make_tuple(py::handle(error), runtime_error));
  classes.not_found = NewError(module, "NotFoundError",
                               "A catalogue file that does not exist, or a test the catalogue does not hold: "
                               "a CatalogueError, and an InputError (a ValueError, as napkin raised before).",
                               py::make_tuple(py::handle(classes.catalogue), py::handle(classes.input)));
  classes.internal = NewError(module, "InternalError",
                              "A bug in napkin (the sentence says what went wrong; please report it). Also "
                              "a RuntimeError, as napkin raised before.",
                              py::make_tuple(py::handle(error), runtime_error));
  py::object finding =
      py::module_::import("collections")
          .attr("namedtuple")("Finding", py::make_tuple("check", "channel", "severity", "detail"),
                              py::arg("module") = "napkin");
  finding.attr("__doc__") =
      "A screening finding (docs/algorithms.md \"Data screening\"), as a test's summary lists them "
      "under \"quality\":\n\n"
      "check    -- what found it, e.g. \"saturation\", \"polarity\", \"implausible\"\n"
      "channel  -- the slot it is about, or None for the whole test\n"
      "severity -- \"info\", \"warning\" or \"error\" (an error fails the test)\n"
      "detail   -- one sentence";
  module.add_object("Finding", finding);
  classes.finding = finding.release().ptr();
}

void RaiseFailure(const app::Failure& failure) {
  const ErrorClasses& classes = Classes();
  switch (failure.category) {
    case app::FailureCategory::kUsage:
    case app::FailureCategory::kInput:
      Raise(classes.input, failure.sentence);
    case app::FailureCategory::kScreening: {
      py::list findings;
      for (const engine::Finding& finding : failure.findings) findings.append(FindingTuple(finding));
      const py::object error = py::reinterpret_borrow<py::object>(classes.screening)(failure.sentence);
      error.attr("findings") = findings;
      PyErr_SetObject(classes.screening, error.ptr());
      throw py::error_already_set();
    }
    case app::FailureCategory::kNotFound:
      Raise(classes.not_found, failure.sentence);
    case app::FailureCategory::kCatalogueBusy:
    case app::FailureCategory::kCatalogue:
      Raise(classes.catalogue, failure.sentence);
    case app::FailureCategory::kOutOfMemory:
      Raise(PyExc_MemoryError, failure.sentence);
    case app::FailureCategory::kInternal:
      break;
  }
  Raise(classes.internal, failure.sentence);
}

void RaiseCatalogueError(const std::string& sentence) { Raise(Classes().catalogue, sentence); }

}  // namespace napkin::python
