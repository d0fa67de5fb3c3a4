// Errors keep their meaning in a run (cli/diagnostics.h, jobs/README.md
// "Errors"): bad data fails its test and the run goes on
// (tests/jobs/scheduler_test.cpp), but a programmer error inside the
// computation is no test's failure: it stops the run, the CLI reports it as
// an internal error to report, and the catalogue stays consistent, so the
// next run resumes where this one stopped.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <exception>
#include <sstream>
#include <stdexcept>
#include <string>

#include "cli/command.h"
#include "cli/diagnostics.h"
#include "common/error.h"
#include "db/job_queue.h"
#include "jobs/scheduler.h"
#include "records/test_inputs.h"
#include "tests/jobs/jobs_test_helpers.h"
#include "tests/support/test_support.h"

namespace napkin {
namespace {

// cli::ReportFailure's status and its stderr line ("level|message").
struct Reported {
  int exit_status;
  std::string text;
};

Reported Report(const std::exception_ptr& error, const std::string& db_path) {
  std::ostringstream captured;
  auto previous = spdlog::default_logger();
  auto sink = std::make_shared<spdlog::sinks::ostream_sink_mt>(captured);
  sink->set_pattern("%l|%v");
  spdlog::set_default_logger(std::make_shared<spdlog::logger>("test", sink));
  const int status = cli::ReportFailure(error, db_path);
  spdlog::set_default_logger(previous);
  std::string text = captured.str();
  if (!text.empty() && text.back() == '\n') text.pop_back();
  return {status, text};
}

TEST(RunInternalError, AProgrammerErrorStopsTheRunUnrecordedAndTheNextRunResumes) {
  napkin::test_support::TempDir dir;
  const std::string path = dir / "catalogue.db";
  constexpr int kTests = 6;
  test_support::AddRandomTests(path, kTests, 800);
  const std::string broken = test_support::TestName(3);
  const records::ResolvedConfig processing = test_support::Processing();

  jobs::RunOptions options;
  options.threads = 1;
  options.poll_interval_s = 0.05;
  options.compute = [&](const records::TestInputs& inputs, const engine::ProcessingConfig& config) {
    if (inputs.external_id == broken) throw std::logic_error("injected: a broken invariant");
    return records::ComputeResult(inputs, config);
  };
  std::exception_ptr error;
  try {
    jobs::RunScheduler(path, processing, options);
  } catch (...) {
    error = std::current_exception();
  }
  ASSERT_TRUE(error) << "the run went on past a programmer error";
  const Reported reported = Report(error, path);
  EXPECT_EQ(reported.exit_status, cli::kExitFailure);
  EXPECT_EQ(reported.text,
            "error|internal error: injected: a broken invariant; this is a bug in napkin, please report it "
            "with the command line that caused it.");

  // Consistent: no test recorded as failed, no lease left behind, the
  // broken test without a result; what was committed stays.
  std::int64_t done_before = 0;
  {
    db::Catalogue catalogue = db::Catalogue::Open(path);
    const auto config = catalogue.FindConfigByHash(processing.record.config_hash);
    ASSERT_TRUE(config);
    const db::StatusCounts counts = db::JobQueue(catalogue).ReadStatusCounts(*config);
    EXPECT_EQ(counts.failed, 0);
    EXPECT_EQ(counts.running, 0);
    EXPECT_EQ(counts.done + counts.pending, kTests);
    EXPECT_FALSE(catalogue.ReadSummary(*catalogue.FindTestByExternalId(broken), *config));
    done_before = counts.done;
  }

  // The next run (the bug fixed) processes the rest, the broken test included.
  options.compute = jobs::ComputeInThreadWorkspace;
  const jobs::RunReport rerun = jobs::RunScheduler(path, processing, options);
  EXPECT_EQ(rerun.failed, 0);
  EXPECT_EQ(rerun.skipped, done_before);
  EXPECT_EQ(rerun.done, kTests - done_before);
  db::Catalogue catalogue = db::Catalogue::Open(path);
  EXPECT_TRUE(catalogue.ReadSummary(*catalogue.FindTestByExternalId(broken), rerun.config));
}

// Bad data is still the test's failure: the run records it and goes on.
TEST(RunInternalError, AnInputErrorFailsItsTestOnly) {
  napkin::test_support::TempDir dir;
  const std::string path = dir / "catalogue.db";
  test_support::AddRandomTests(path, 4, 800);
  const std::string bad = test_support::TestName(1);
  jobs::RunOptions options;
  options.threads = 1;
  options.poll_interval_s = 0.05;
  options.compute = [&](const records::TestInputs& inputs, const engine::ProcessingConfig& config) {
    if (inputs.external_id == bad) throw InputError("test '" + bad + "': injected bad data.");
    return records::ComputeResult(inputs, config);
  };
  const jobs::RunReport report = jobs::RunScheduler(path, test_support::Processing(), options);
  EXPECT_EQ(report.done, 3);
  EXPECT_EQ(report.failed, 1);
  db::Catalogue catalogue = db::Catalogue::Open(path);
  const std::vector<db::JobFailure> failures =
      db::JobQueue(catalogue).ReadStatusCounts(report.config).failures;
  ASSERT_EQ(failures.size(), 1u);
  EXPECT_EQ(failures[0].error, "test '" + bad + "': injected bad data.");
}

}  // namespace
}  // namespace napkin
