#pragma once
// What the stages of one batch run share (jobs/README.md): the processing
// config, the options, the lease owner, the tokens that bound the tests in
// memory, the counters and the abort flag. Internal to jobs/: each stage
// (lease_keeper.h, job_reader.h, test_computation.h, result_writer.h) takes
// the RunContext and its own catalogue connection, nothing else.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "db/catalogue.h"
#include "db/job_queue.h"
#include "engine/pipeline.h"
#include "jobs/scheduler.h"
#include "records/test_inputs.h"

namespace napkin::jobs {

using SteadyClock = std::chrono::steady_clock;

inline double SecondsSince(SteadyClock::time_point start) {
  return std::chrono::duration<double>(SteadyClock::now() - start).count();
}

// One test on its way through the pipeline.
struct WorkItem {
  db::Job job;
  records::TestInputs inputs;
  engine::ProcessedTest processed;
  std::optional<std::string> error;  // the failure sentence, if the test failed
  std::int64_t samples = 0;
};
using ItemPtr = std::unique_ptr<WorkItem>;

// Jobs this run holds leases on and has not committed yet.
class LeaseBook {
 public:
  void Add(db::JobId job) {
    std::lock_guard lock(mutex_);
    jobs_.insert(job);
  }
  void Remove(db::JobId job) {
    std::lock_guard lock(mutex_);
    jobs_.erase(job);
  }
  std::vector<db::JobId> Snapshot() const {
    std::lock_guard lock(mutex_);
    return {jobs_.begin(), jobs_.end()};
  }

 private:
  mutable std::mutex mutex_;
  std::set<db::JobId> jobs_;
};

// The tokens that bound the tests in memory, the peak of tests in memory,
// and the abort flag a failing stage raises.
class RunState {
 public:
  explicit RunState(int tokens) : free_tokens_(tokens) {}

  // Takes a token for a test about to be read; waits at most `wait` while
  // every token is taken. False if none was free (or the run is aborting).
  bool AcquireToken(std::chrono::milliseconds wait) {
    std::unique_lock lock(mutex_);
    if (!token_freed_.wait_for(lock, wait, [this] { return free_tokens_ > 0 || aborted_; }) || aborted_)
      return false;
    --free_tokens_;
    return true;
  }
  void ReleaseTokens(int count) {
    {
      std::lock_guard lock(mutex_);
      free_tokens_ += count;
    }
    token_freed_.notify_all();
  }
  // A stage failed: the reader stops, the other stages drain.
  void Abort() {
    {
      std::lock_guard lock(mutex_);
      aborted_ = true;
    }
    token_freed_.notify_all();
  }
  bool aborted() const {
    std::lock_guard lock(mutex_);
    return aborted_;
  }

  void Read() {
    const int now = ++in_memory_;
    int peak = peak_in_memory_.load();
    while (now > peak && !peak_in_memory_.compare_exchange_weak(peak, now)) {
    }
  }
  void Committed(int count) { in_memory_ -= count; }
  int peak_in_memory() const { return peak_in_memory_.load(); }

 private:
  mutable std::mutex mutex_;
  std::condition_variable token_freed_;
  int free_tokens_;
  bool aborted_ = false;
  std::atomic<int> in_memory_{0};
  std::atomic<int> peak_in_memory_{0};
};

// Tests read and waiting for a compute thread: from the reader thread to the
// pipeline's input filter. Unbounded itself: every test in it holds a token.
class ReadyQueue {
 public:
  void Push(ItemPtr item) {
    {
      std::lock_guard lock(mutex_);
      items_.push_back(std::move(item));
    }
    changed_.notify_one();
  }
  // No more tests will come.
  void Close() {
    {
      std::lock_guard lock(mutex_);
      closed_ = true;
    }
    changed_.notify_all();
  }
  // The next test; waits for one; nullptr once closed and empty.
  ItemPtr Pop() {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return !items_.empty() || closed_; });
    if (items_.empty()) return nullptr;
    ItemPtr item = std::move(items_.front());
    items_.pop_front();
    return item;
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<ItemPtr> items_;
  bool closed_ = false;
};

// The shared state of one run. The report's counters are each written by one
// stage (reader: read_s, reclaimed; writer: done, failed, lost, samples,
// write_s) and read by RunScheduler only after the stages have ended.
struct RunContext {
  // `threads`: the compute threads (RunOptions::threads resolved).
  RunContext(const records::ResolvedConfig& processing, const RunOptions& options, int threads,
             const ProgressCallback& progress, const std::atomic<bool>* stop)
      : processing(processing),
        options(options),
        progress(progress),
        stop(stop),
        start(SteadyClock::now()),
        state(threads * options.tests_in_flight_per_thread) {
    report.threads = threads;
    report.max_tests_in_flight = threads * options.tests_in_flight_per_thread;
  }
  RunContext(const RunContext&) = delete;
  RunContext& operator=(const RunContext&) = delete;

  const records::ResolvedConfig& processing;  // the config (with its storage choice) and its record
  const RunOptions& options;
  const ProgressCallback& progress;
  const std::atomic<bool>* stop;  // set by a signal handler: end after the tests in flight
  const SteadyClock::time_point start;
  RunReport report;       // owner, config id, threads, tokens, and the counters
  std::string work_path;  // the catalogue or results file holding the jobs and results
  LeaseBook leases;
  RunState state;
  std::atomic<double> compute_s{0.0};  // ProcessTest, summed over the compute threads
};

}  // namespace napkin::jobs
