#pragma once
// The one place where the napkin CLI turns what went wrong into stderr text
// and an exit status (osmium-tool's main is the model: every exception type
// has its status and, where the user can act, a hint).
//
//   exception                      exit  stderr (one line)
//   CLI::ParseError (options)       2    napkin: <sentence> (ReportOptionError)
//   UsageError                      2    napkin: <sentence>
//   InputError (bad data, files)    1    napkin: <sentence>
//   db::DatabaseError, busy         1    napkin: catalogue 'F' is busy: ... (hint: wait, retry)
//   db::DatabaseError, disk full,   1    napkin: catalogue 'F' could not be written: the disk ... is
//     damaged, read-only                 full / is damaged / cannot be written ... (hint, no SQLite text)
//   db::DatabaseError, other        1    napkin: catalogue 'F': <SQLite text>
//   std::bad_alloc                  1    napkin: out of memory ... (hint)
//   anything else (logic_error,     1    napkin: internal error: <what>; this is a bug in napkin,
//   invalid_argument, ...)                please report it with the command line that caused it.
//
// Every diagnostic goes through spdlog (SetUpLogging): errors print as
// "napkin: <sentence>", warnings as "napkin: warning: <sentence>", progress
// and run information as time-stamped "info" lines (none with --quiet).
#include <exception>
#include <string>

namespace CLI {
class ParseError;
}  // namespace CLI

namespace napkin::cli {

// Installs the CLI's stderr logger as spdlog's default logger.
void SetUpLogging();

// --quiet: warnings and errors only, no information lines.
void SetQuietLogging();

// Logs a refused command line (CLI11's ParseError other than --help and
// --version: an unknown or missing option, a value an option check of
// cli/option_checks.h refused) as one sentence and returns kExitUsage.
int ReportOptionError(const CLI::ParseError& error);

// What `error` means for the user, as described above: its exit status,
// whether it is bad input (UsageError, InputError: the Python module raises
// ValueError for these, RuntimeError for the rest) and the sentence.
// `db_path` names the catalogue in database errors.
struct Failure {
  int exit_status;
  bool bad_input;
  std::string sentence;
};
Failure DescribeFailure(const std::exception_ptr& error, const std::string& db_path);

// Logs DescribeFailure's sentence of `error` (the exception in flight) and
// returns its exit status.
int ReportFailure(const std::exception_ptr& error, const std::string& db_path);

}  // namespace napkin::cli
