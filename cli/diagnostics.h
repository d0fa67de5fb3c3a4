#pragma once
// The one place where the napkin CLI turns what went wrong into stderr text
// and an exit status (osmium-tool's main is the model: every exception type
// has its status and, where the user can act, a hint). The sentence and its
// category are app/failure.h's; the exit status is the category's:
//
//   CLI::ParseError (options)                2    napkin: <sentence> (ReportOptionError)
//   kUsage (UsageError)                      2    napkin: <sentence>
//   kInput (InputError: bad data, files)     1    napkin: <sentence>
//   kCatalogueBusy, kCatalogue (database)    1    napkin: catalogue 'F' ... (app/failure.h)
//   kOutOfMemory (std::bad_alloc)            1    napkin: out of memory ... (hint)
//   kInternal (anything else)                1    napkin: internal error: <what>; this is a bug ...
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

// From now on warnings and errors carry the information lines' timestamp too
// ("2026-11-27T10:15:02.123 napkin: warning: ..."): a long-running service's
// log (`napkin serve` once listening), read later, needs each line's time.
void TimestampEveryLogLine();

// Logs a refused command line (CLI11's ParseError other than --help and
// --version: an unknown or missing option, a value an option check of
// cli/option_checks.h refused) as one sentence and returns kExitUsage.
int ReportOptionError(const CLI::ParseError& error);

// Logs app::DescribeFailure's sentence of `error` (the exception in flight)
// and returns its category's exit status.
int ReportFailure(const std::exception_ptr& error, const std::string& db_path);

}  // namespace napkin::cli
