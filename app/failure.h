#pragma once
// What went wrong, for any front end: a category and one sentence (README:
// every error is one sentence naming the file, option or test). The
// command line maps the category to its exit status (cli/diagnostics.h), the
// Python module to an exception class (python/py_bindings.h).
//
//   exception                      category         sentence
//   UsageError                     kUsage           <its sentence>
//   engine::ScreeningFailure       kScreening       <its sentence> (and its findings)
//   NotFoundError (no such         kNotFound        <its sentence>
//     catalogue, test)
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
#include <utility>
#include <vector>

#include "engine/summary.h"

namespace napkin::app {

enum class FailureCategory {
  kUsage,
  kInput,
  kScreening,
  kNotFound,
  kCatalogueBusy,
  kCatalogue,
  kOutOfMemory,
  kInternal
};

struct Failure {
  Failure(FailureCategory category_, std::string sentence_, std::vector<engine::Finding> findings_ = {})
      : category(category_), sentence(std::move(sentence_)), findings(std::move(findings_)) {}

  FailureCategory category;
  std::string sentence;
  std::vector<engine::Finding> findings;  // kScreening: what screening found

  // Bad input the user can correct: a request (kUsage), data (kInput, kScreening),
  // a catalogue or test that is not there (kNotFound).
  bool BadInput() const {
    return category == FailureCategory::kUsage || category == FailureCategory::kInput ||
           category == FailureCategory::kScreening || category == FailureCategory::kNotFound;
  }
};

// What `error` means for the user, as described above; `db_path` names the
// catalogue in database errors.
Failure DescribeFailure(const std::exception_ptr& error, const std::string& db_path);

}  // namespace napkin::app
