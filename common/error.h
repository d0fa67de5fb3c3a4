#pragma once
// Error types shared by every folder (engine, formats, db, records, ingest,
// jobs, cli). Each message is one sentence that names the file, test, channel
// or row at fault; app::DescribeFailure (app/failure.h) sorts each type into
// a failure category, and cli/diagnostics.cpp (ReportFailure) gives the
// category its exit status.
#include <stdexcept>
#include <string>

namespace napkin {

// Bad input data or definitions (user-facing, exit status 1).
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Options that contradict each other or a malformed option value that the
// argument parser cannot see (exit status 2, like CLI11's own usage errors).
class UsageError : public InputError {
 public:
  using InputError::InputError;
};

// Something asked for that is not there: a catalogue file that does not
// exist, a test the catalogue does not hold (exit status 1, as InputError;
// the Python module raises napkin.NotFoundError, a napkin.CatalogueError).
class NotFoundError : public InputError {
 public:
  using InputError::InputError;
};

// An array definition that cannot be solved (duplicate slots, zero axis,
// rank-deficient linear set, unknown unit).
class InvalidArrayError : public InputError {
 public:
  using InputError::InputError;
};

}  // namespace napkin
