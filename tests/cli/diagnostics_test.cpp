// The CLI's one error map (cli/diagnostics.h): every exception type gets its
// exit status and its one line on stderr.
#include "cli/diagnostics.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>
#include <sqlite3.h>

#include <new>
#include <sstream>
#include <stdexcept>

#include "cli/command.h"
#include "common/error.h"
#include "db/sqlite.h"

namespace napkin::cli {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

// Runs ReportFailure on `error` with a logger that writes the message alone.
struct Reported {
  int exit_status;
  std::string text;
};

template <typename Exception>
Reported Report(const Exception& error) {
  std::ostringstream captured;
  auto previous = spdlog::default_logger();
  auto sink = std::make_shared<spdlog::sinks::ostream_sink_mt>(captured);
  sink->set_pattern("%l|%v");
  spdlog::set_default_logger(std::make_shared<spdlog::logger>("test", sink));
  const int status = ReportFailure(std::make_exception_ptr(error), "cat.db");
  spdlog::set_default_logger(previous);
  std::string text = captured.str();
  if (!text.empty() && text.back() == '\n') text.pop_back();
  return {status, text};
}

TEST(ReportFailure, UsageErrorsExitTwo) {
  const Reported reported = Report(UsageError("--test-id names one test, but the paths hold 3 inputs."));
  EXPECT_EQ(reported.exit_status, kExitUsage);
  EXPECT_EQ(reported.text, "error|--test-id names one test, but the paths hold 3 inputs.");
}

TEST(ReportFailure, InputErrorsExitOneWithTheirSentence) {
  const Reported reported = Report(InvalidArrayError("array 'x' has a zero axis."));
  EXPECT_EQ(reported.exit_status, kExitFailure);
  EXPECT_EQ(reported.text, "error|array 'x' has a zero axis.");
}

TEST(ReportFailure, BusyCatalogueSaysWhatToDo) {
  const Reported reported = Report(db::DatabaseError("SQLite error 'database is locked' (5)", SQLITE_BUSY));
  EXPECT_EQ(reported.exit_status, kExitFailure);
  EXPECT_THAT(reported.text, StartsWith("error|catalogue 'cat.db' is busy"));
  EXPECT_THAT(reported.text, HasSubstr("run the command again"));
  // Any SQLite client may be the holder, and the sentence ends as a sentence (issue 42, point 11:
  // it blamed "another napkin process" and ended in SQLite's own text).
  EXPECT_EQ(
      reported.text,
      "error|catalogue 'cat.db' is busy: another process (a napkin command, sqlite3 or any other SQLite "
      "client) has held its lock longer than the wait allows; run the command again when that process has "
      "finished.");
}

TEST(ReportFailure, OtherDatabaseErrorsNameTheCatalogue) {
  const Reported reported = Report(db::DatabaseError("SQLite error 'disk I/O error' (10)", SQLITE_IOERR));
  EXPECT_EQ(reported.exit_status, kExitFailure);
  EXPECT_EQ(reported.text, "error|catalogue 'cat.db': SQLite error 'disk I/O error' (10)");
}

TEST(ReportFailure, OutOfMemoryHasAHint) {
  const Reported reported = Report(std::bad_alloc());
  EXPECT_EQ(reported.exit_status, kExitFailure);
  EXPECT_THAT(reported.text, StartsWith("error|out of memory"));
}

TEST(ReportFailure, ProgrammerErrorsSayTheyAreBugs) {
  for (const Reported& reported : {Report(std::invalid_argument("RunOptions: threads")),
                                   Report(std::logic_error("transaction committed twice"))}) {
    EXPECT_EQ(reported.exit_status, kExitFailure);
    EXPECT_THAT(reported.text, StartsWith("error|internal error: "));
    EXPECT_THAT(reported.text, HasSubstr("this is a bug in napkin, please report it"));
  }
}

TEST(ReportFailure, UnknownExceptionsAreInternalErrors) {
  const Reported reported = Report(42);
  EXPECT_EQ(reported.exit_status, kExitFailure);
  EXPECT_THAT(reported.text, HasSubstr("internal error: an unknown exception"));
}

}  // namespace
}  // namespace napkin::cli
