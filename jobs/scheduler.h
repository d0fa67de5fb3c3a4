#pragma once
// The batch scheduler (README "Batch runs", docs/architecture.md): claims the jobs of
// one processing config from the catalogue, runs the transform core
// (engine::ProcessTest) on them in parallel with oneTBB and stores the
// results back, so that an interrupted or crashed run can simply be started
// again.
//
// Shape (docs/architecture.md "The batch scheduler"): reading and writing
// never take a compute thread,
//   reader thread  — its own catalogue connection: claims a few jobs at a
//                    time under a lease and reads each test's signals, array
//                    and initial state ahead of the compute threads;
//   compute        — a tbb::task_arena of exactly `threads` threads running a
//                    tbb::parallel_pipeline of records::ComputeResult; an
//                    InputError (bad data) or a screening error fails the
//                    test, any other exception (a bug) stops the run;
//                    finished tests go to the writer's queue;
//   writer thread  — its own connection: commits results in batches (ONE
//                    transaction per batch; each test's result row, findings,
//                    derived channels and job state together or not at all)
//                    while the compute threads go on computing.
// A test holds one of `threads x tests_in_flight_per_thread` tokens from its
// read until the writer takes it into a batch, so at most that many tests
// plus one batch being committed are in memory, however many tests the run
// has. A heartbeat thread (its own connection) renews the leases of claimed
// jobs.
//
// Guarantees: SIGKILL at any moment loses at most the uncommitted tests (the
// leases of the dead process expire, or are released at once by the next run
// on the same host, which sees the process is gone); a job is completed only
// by the lease holder (a result whose lease passed to another worker is
// dropped), so concurrent runs on one file never store a test twice; a stop
// request ends claiming, drains the tests read, computes and commits them
// and returns the leases of jobs claimed but not read; a failing catalogue
// stops the reader, drains the pipeline, releases the leases and throws.
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>

#include "db/catalogue.h"
#include "db/job_queue.h"
#include "engine/processing.h"
#include "records/config_record.h"
#include "records/test_inputs.h"

namespace napkin::jobs {

// records::ComputeResult in an engine::Workspace kept by the calling thread
// (thread_local: one per compute thread of the run's arena, kept while the
// thread lives), so a compute thread's tests reuse the memory of the one
// before (engine/pipeline.h Workspace). The same result, bit for bit; with
// storage.derived_channels none, only the series the summary reads
// (engine::SeriesKept::kSummary: the writer stores the summary alone).
engine::ProcessedTest ComputeInThreadWorkspace(const records::TestInputs& inputs,
                                               const engine::ProcessingConfig& config);

struct RunOptions {
  db::JobScope scope;                  // tests to process (--series, --test, --shard); empty: all
  bool force = false;                  // --force: recompute tests whose results are up to date
  bool outdated = false;               // --outdated: also recompute results of another napkin version
  int threads = 0;                     // --threads: worker threads; 0 = all cores
  int tests_in_flight_per_thread = 4;  // tokens per thread (read, not yet being committed): bounds memory
  int claim_batch = 4;                 // jobs claimed per claim transaction
  int commit_batch = 16;               // tests per result transaction, at most; the writer commits
                                       // sooner when waiting would leave < 2 tokens per thread
  double commit_interval_s = 1.0;      // ... or when the oldest uncommitted result is this old
  double lease_s = 120.0;              // job lease; renewed every lease_s / 4 while the job is in flight
  double poll_interval_s = 0.5;        // wait between claims while other workers hold the remaining jobs
  // --results: when set, the catalogue is only read (opened immutable, so
  // many nodes may share it) and the jobs and results go to this results
  // file (db/results_file.h), created if missing; empty: both in the catalogue.
  std::string results_path;
  // The computation of one test on a compute thread: ComputeInThreadWorkspace.
  // A test puts a failing one here to see how the run handles it
  // (tests/cli/run_internal_error_test.cpp).
  std::function<engine::ProcessedTest(const records::TestInputs&, const engine::ProcessingConfig&)> compute =
      ComputeInThreadWorkspace;
  // Whether RunScheduler raises glibc's malloc thresholds so freed memory is
  // kept for reuse (util/malloc_tuning.h; jobs/README.md "Memory"): each
  // test's result is allocated on a compute thread and freed on the writer
  // thread once stored, which no workspace covers. Process-wide, so a
  // program's choice: `napkin run` keeps the default; a host process that
  // embeds the scheduler and tunes its allocator itself sets it to false.
  bool keep_freed_memory = true;

  // Throws std::invalid_argument naming the field out of range.
  void Check() const;
};

struct RunProgress {
  std::int64_t total = 0;   // jobs to process when the run started
  std::int64_t done = 0;    // stored by this run so far
  std::int64_t failed = 0;  // recorded as failed by this run so far
  double elapsed_s = 0.0;
};
// Called after every committed batch, from the writer thread.
using ProgressCallback = std::function<void(const RunProgress&)>;

struct RunReport {
  std::string owner;           // this run's lease owner id (host:pid:random)
  db::ConfigId config{};       // the config's catalogue key
  std::int64_t total = 0;      // jobs to process when the run started
  std::int64_t skipped = 0;    // tests in scope already up to date
  std::int64_t done = 0;       // results stored
  std::int64_t failed = 0;     // failures recorded
  std::int64_t lost = 0;       // results dropped because the lease had passed to another worker
  std::int64_t released = 0;   // jobs claimed but not started (stop), returned to the queue
  std::int64_t reclaimed = 0;  // jobs of dead local workers returned to the queue
  std::int64_t samples = 0;    // input samples (rows x channels) of the processed tests
  int threads = 0;
  int max_tests_in_flight = 0;   // tokens: threads x tests_in_flight_per_thread
  int peak_tests_in_memory = 0;  // tests read and not yet committed, at most (<= tokens + a batch)
  bool stopped = false;          // ended by the stop flag
  double wall_s = 0.0;
  double read_s = 0.0;     // reading inputs (reader thread, overlaps computing)
  double compute_s = 0.0;  // ProcessTest, summed over threads
  double write_s = 0.0;    // result transactions (writer thread, overlaps computing)
};

// Processes every test in `options.scope` whose result for `processing` is
// missing, failed, (with outdated) computed by another napkin version or
// (with force) present (db::JobQueue::EnqueueMissing); see the file comment.
// With options.results_path the inputs come from the catalogue at `db_path`
// opened read-only and immutable, and everything written (config, jobs,
// results) goes to the results file. `stop` (set by a signal handler) ends the
// run after the tests in flight. Throws InputError for a catalogue that cannot
// be opened; db::DatabaseError when it fails during the run, or what a
// computation throws but InputError (a bug), after releasing its leases.
RunReport RunScheduler(const std::string& db_path, const records::ResolvedConfig& processing,
                       const RunOptions& options, const ProgressCallback& progress = {},
                       const std::atomic<bool>* stop = nullptr);

// "host:pid:random": unique per scheduler, readable in the jobs table.
std::string MakeOwnerId();
// True when `owner` (a MakeOwnerId value) names a process on this host that
// no longer exists (or this process's pid, reused, with an owner id that no
// scheduler of this process holds), so its leases can be released at once.
bool IsDeadLocalOwner(const std::string& owner);

}  // namespace napkin::jobs
