#pragma once
// What went wrong, for any front end: a category and one sentence (README:
// every error is one sentence naming the file, option or test). The
// command line maps the category to its exit status (cli/diagnostics.h), the
// Python module to an exception class (python/py_bindings.h).
//
//   exception                      category         sentence
//   UsageError                     kUsage           <its sentence>
//   InputError (bad data, files)   kInput           <its sentence>
//   db::DatabaseError, busy        kCatalogueBusy   catalogue 'F' is busy: ... (hint: wait, retry)
//   db::DatabaseError, disk full,  kCatalogue       catalogue 'F' could not be written: the disk ... is
//     damaged, read-only                            full / is damaged / cannot be written ... (hint, no
//                                                   SQLite text)
//   db::DatabaseError, other       kCatalogue       catalogue 'F': <SQLite text>
//   std::bad_alloc                 kOutOfMemory     out of memory ... (hint)
//   anything else (logic_error,    kInternal        internal error: <what>; this is a bug in napkin,
//   invalid_argument, ...)                          please report it with the command line that caused it.
#include <exception>
#include <string>

namespace napkin::app {

enum class FailureCategory { kUsage, kInput, kCatalogueBusy, kCatalogue, kOutOfMemory, kInternal };

struct Failure {
  FailureCategory category;
  std::string sentence;

  // Bad input: a request (kUsage) or data (kInput) the user can correct.
  bool BadInput() const { return category == FailureCategory::kUsage || category == FailureCategory::kInput; }
};

// What `error` means for the user, as described above; `db_path` names the
// catalogue in database errors.
Failure DescribeFailure(const std::exception_ptr& error, const std::string& db_path);

}  // namespace napkin::app
