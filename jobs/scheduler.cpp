#include "jobs/scheduler.h"

#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/parallel_pipeline.h>
#include <oneapi/tbb/task_arena.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <signal.h>
#include <spdlog/spdlog.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "common/error.h"
#include "db/results_file.h"
#include "engine/pipeline.h"
#include "records/array_record.h"

namespace napkin::jobs {

namespace {

using SteadyClock = std::chrono::steady_clock;

double SecondsSince(SteadyClock::time_point start) {
  return std::chrono::duration<double>(SteadyClock::now() - start).count();
}

std::string HostName() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "localhost";
  return name;
}

// Owner ids of the schedulers running in this process: an owner with our
// pid that is not among them belonged to a dead process whose pid was reused.
class LiveOwners {
 public:
  static LiveOwners& Get() {
    static LiveOwners owners;
    return owners;
  }
  void Add(const std::string& owner) {
    std::lock_guard lock(mutex_);
    owners_.insert(owner);
  }
  void Remove(const std::string& owner) {
    std::lock_guard lock(mutex_);
    owners_.erase(owner);
  }
  bool Contains(const std::string& owner) const {
    std::lock_guard lock(mutex_);
    return owners_.count(owner) > 0;
  }

 private:
  mutable std::mutex mutex_;
  std::set<std::string> owners_;
};

// Registers an owner id for the life of a scheduler.
class LiveOwnerScope {
 public:
  explicit LiveOwnerScope(std::string owner) : owner_(std::move(owner)) { LiveOwners::Get().Add(owner_); }
  ~LiveOwnerScope() { LiveOwners::Get().Remove(owner_); }
  LiveOwnerScope(const LiveOwnerScope&) = delete;
  LiveOwnerScope& operator=(const LiveOwnerScope&) = delete;

 private:
  std::string owner_;
};

// One test on its way through the pipeline.
struct WorkItem {
  db::Job job;
  std::string external_id;
  std::shared_ptr<const engine::ArrayGeometry> array;
  engine::TestSignals signals;
  engine::InitialState initial;
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

// Renews the leases in a LeaseBook every lease_s / 4 on its own connection,
// so a test that computes for long does not lose its job to another worker.
class Heartbeat {
 public:
  Heartbeat(std::string db_path, db::CatalogueOptions catalogue_options, const LeaseBook& book,
            std::string owner, double lease_s)
      : db_path_(std::move(db_path)),
        catalogue_options_(std::move(catalogue_options)),
        book_(book),
        owner_(std::move(owner)),
        lease_s_(lease_s),
        thread_([this] { Loop(); }) {}
  ~Heartbeat() {
    {
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    thread_.join();
  }
  Heartbeat(const Heartbeat&) = delete;
  Heartbeat& operator=(const Heartbeat&) = delete;

 private:
  void Loop() {
    try {
      std::optional<db::Catalogue> catalogue;
      const auto period = std::chrono::duration<double>(lease_s_ / 4.0);
      std::unique_lock lock(mutex_);
      while (!wake_.wait_for(lock, period, [this] { return stopping_; })) {
        lock.unlock();
        if (!catalogue) catalogue.emplace(db::Catalogue::Open(db_path_, catalogue_options_));
        db::JobQueue queue(*catalogue);
        // A job committed between the snapshot and its renewal is simply
        // not renewed (RenewLease is false for a job no longer running).
        for (const db::JobId job : book_.Snapshot()) queue.RenewLease(job, owner_, lease_s_);
        lock.lock();
      }
    } catch (const std::exception& error) {
      // The run goes on; its leases may then expire and its results be
      // dropped as lost (never stored twice).
      spdlog::error("lease renewal stopped: {}", error.what());
    }
  }

  std::string db_path_;
  db::CatalogueOptions catalogue_options_;
  const LeaseBook& book_;
  std::string owner_;
  double lease_s_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread thread_;  // last: started after every other member is ready
};

// Shared state of the stages: the tokens that bound the tests in memory, the
// counters, and the abort flag a failing stage raises.
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

// The write-ahead log is restarted once longer than this (64 MiB, SQLite's
// journal_size_limit of the catalogue: the file is cut back to it).
constexpr std::int64_t kMaxWalBytes = 64 << 20;

// The writer thread: takes computed tests from a queue and commits them in
// batches on its own connection, one transaction per batch, each test's rows
// inside it all-or-nothing (a savepoint). The compute threads only append to
// the queue, so they go on computing while a batch commits.
class ResultWriter {
 public:
  ResultWriter(db::Catalogue& catalogue, db::ConfigId config, std::string solver,
               engine::DerivedStorage storage, std::string owner, const RunOptions& options, int tokens,
               LeaseBook& book, RunState& state, RunReport& report, const ProgressCallback& progress,
               SteadyClock::time_point start)
      : catalogue_(catalogue),
        queue_(catalogue),
        config_(config),
        solver_(std::move(solver)),
        storage_(storage),
        owner_(std::move(owner)),
        options_(options),
        // Commit once the queue holds this many tests: waiting for more would
        // leave fewer than two tokens per thread for reading and computing.
        commit_target_(static_cast<std::size_t>(
            std::clamp(tokens - 2 * report.threads, 1, std::max(1, options.commit_batch)))),
        book_(book),
        state_(state),
        report_(report),
        progress_(progress),
        start_(start),
        thread_([this] { Loop(); }) {}
  ~ResultWriter() { Join(); }
  ResultWriter(const ResultWriter&) = delete;
  ResultWriter& operator=(const ResultWriter&) = delete;

  // A computed test (the pipeline's output filter). Never blocks for long:
  // the tokens bound the queue.
  void Push(ItemPtr item) {
    {
      std::lock_guard lock(mutex_);
      queue_items_.push_back(Queued{std::move(item), SteadyClock::now()});
    }
    changed_.notify_one();
  }
  // Commit what is queued now rather than wait for a full batch.
  void RequestFlush() {
    {
      std::lock_guard lock(mutex_);
      flush_requested_ = true;
    }
    changed_.notify_one();
  }
  // No more tests: commits the rest and ends the thread; returns the error
  // that stopped the commits, if any.
  std::exception_ptr Join() {
    {
      std::lock_guard lock(mutex_);
      closed_ = true;
    }
    changed_.notify_one();
    if (thread_.joinable()) thread_.join();
    return error_;
  }

 private:
  enum class Outcome { kDone, kFailed, kLost };
  struct Queued {
    ItemPtr item;
    SteadyClock::time_point arrived;
  };

  void Loop() {
    for (;;) {
      std::vector<ItemPtr> batch;
      {
        std::unique_lock lock(mutex_);
        for (;;) {
          if (queue_items_.empty()) {
            if (closed_) return;
            flush_requested_ = false;
            changed_.wait(lock);
            continue;
          }
          if (closed_ || flush_requested_ || queue_items_.size() >= commit_target_) break;
          const auto due =
              queue_items_.front().arrived + std::chrono::duration_cast<SteadyClock::duration>(
                                                 std::chrono::duration<double>(options_.commit_interval_s));
          if (SteadyClock::now() >= due) break;
          changed_.wait_until(lock, due);
        }
        flush_requested_ = false;
        const std::size_t count =
            std::min(queue_items_.size(), static_cast<std::size_t>(options_.commit_batch));
        for (std::size_t i = 0; i < count; ++i) {
          batch.push_back(std::move(queue_items_.front().item));
          queue_items_.pop_front();
        }
      }
      // The batch leaves the tokens' count: the reader may read the next tests.
      state_.ReleaseTokens(static_cast<int>(batch.size()));
      if (!error_) {
        try {
          Commit(batch);
        } catch (...) {
          // The run ends; the tests that reach the queue from now on are dropped.
          error_ = std::current_exception();
          state_.Abort();
        }
      }
      if (error_) state_.Committed(static_cast<int>(batch.size()));
    }
  }

  void Commit(const std::vector<ItemPtr>& batch) {
    const auto write_start = SteadyClock::now();
    std::vector<Outcome> outcomes;
    outcomes.reserve(batch.size());
    {
      db::Transaction transaction = catalogue_.BeginTransaction();
      for (const ItemPtr& item : batch) {
        db::Transaction test = catalogue_.BeginTransaction();  // a savepoint: this test's rows or none
        bool held = false;
        if (item->error) {
          if (!item->processed.summary.findings.empty())
            catalogue_.WriteFindings(item->job.test_id, config_, item->processed.summary.findings);
          held = queue_.FailJob(item->job.id, owner_, *item->error);
        } else {
          catalogue_.WriteResult(item->job.test_id, config_, item->processed.summary, solver_,
                                 &item->processed.kinematics,
                                 options_.store_kinematics ? storage_ : engine::DerivedStorage::kNone);
          held = queue_.CompleteJob(item->job.id, owner_);
        }
        // Without the lease another worker owns the job now: drop our rows.
        if (held) test.Commit();
        outcomes.push_back(!held ? Outcome::kLost : item->error ? Outcome::kFailed : Outcome::kDone);
      }
      transaction.Commit();
    }
    // The reader never pauses, so the log would otherwise grow by every
    // byte written (db::Catalogue::RestartWalIfLonger).
    catalogue_.RestartWalIfLonger(kMaxWalBytes);
    // Counted only once durable.
    for (std::size_t i = 0; i < batch.size(); ++i) {
      const WorkItem& item = *batch[i];
      book_.Remove(item.job.id);
      switch (outcomes[i]) {
        case Outcome::kDone:
          ++report_.done;
          report_.samples += item.samples;
          break;
        case Outcome::kFailed:
          ++report_.failed;
          report_.samples += item.samples;
          spdlog::warn("test '{}' failed: {}", item.external_id, *item.error);
          break;
        case Outcome::kLost:
          ++report_.lost;
          spdlog::warn("test '{}': the job's lease passed to another worker; its result was not stored",
                       item.external_id);
          break;
      }
    }
    state_.Committed(static_cast<int>(batch.size()));
    report_.write_s += SecondsSince(write_start);
    if (progress_) progress_(RunProgress{report_.total, report_.done, report_.failed, SecondsSince(start_)});
  }

  db::Catalogue& catalogue_;
  db::JobQueue queue_;  // on catalogue_: job states commit with the results
  db::ConfigId config_;
  std::string solver_;
  engine::DerivedStorage storage_;  // processing config storage.derived_channels
  std::string owner_;
  const RunOptions& options_;
  std::size_t commit_target_;
  LeaseBook& book_;
  RunState& state_;
  RunReport& report_;  // done, failed, lost, samples, write_s: this thread's alone until Join
  const ProgressCallback& progress_;
  SteadyClock::time_point start_;
  std::exception_ptr error_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Queued> queue_items_;
  bool flush_requested_ = false;
  bool closed_ = false;
  std::thread thread_;  // last: started after every other member is ready
};

// The reader thread: claims jobs a few at a time (in `queue_catalogue`, on
// its own connection) and reads their tests (from `catalogue`: the same one,
// or the read-only catalogue of a results-file run) ahead of the compute
// threads, one token per test.
class JobReader {
 public:
  JobReader(db::Catalogue& catalogue, db::Catalogue& queue_catalogue, db::ConfigId config, std::string owner,
            const RunOptions& options, LeaseBook& book, RunState& state, ReadyQueue& ready,
            ResultWriter& writer, RunReport& report, const std::atomic<bool>* stop)
      : catalogue_(catalogue),
        queue_(queue_catalogue),
        config_(config),
        owner_(std::move(owner)),
        options_(options),
        book_(book),
        state_(state),
        ready_(ready),
        writer_(writer),
        report_(report),
        stop_(stop),
        thread_([this] { Loop(); }) {}
  ~JobReader() { Join(); }
  JobReader(const JobReader&) = delete;
  JobReader& operator=(const JobReader&) = delete;

  // Waits for the thread (it ends when nothing is left to claim, on a stop
  // request or when the run aborts); returns its error, if any.
  std::exception_ptr Join() {
    if (thread_.joinable()) thread_.join();
    return error_;
  }
  bool stopped() const { return stopped_; }

 private:
  void Loop() {
    try {
      while (!Stopping()) {
        if (!state_.AcquireToken(std::chrono::milliseconds(50))) continue;
        if (claimed_.empty() && !Claim()) {
          state_.ReleaseTokens(1);
          break;
        }
        ready_.Push(ReadNext());
      }
    } catch (...) {
      error_ = std::current_exception();
      state_.Abort();
    }
    ready_.Close();
  }

  ItemPtr ReadNext() {
    const auto read_start = SteadyClock::now();
    auto item = std::make_unique<WorkItem>();
    item->job = claimed_.front();
    claimed_.pop_front();
    const db::TestRow test = catalogue_.ReadTest(item->job.test_id);
    item->external_id = test.external_id;
    item->initial = test.initial_state;
    item->signals = catalogue_.ReadTestSignals(item->job.test_id);
    item->samples = static_cast<std::int64_t>(item->signals.samples.size());
    try {
      item->array = Array(test.array_id);
    } catch (const InputError& error) {
      item->error = error.what();
    }
    state_.Read();
    report_.read_s += SecondsSince(read_start);
    return item;
  }

  // True once a stop is requested (or a stage failed): no more claims.
  bool Stopping() {
    if (stop_ != nullptr && stop_->load()) stopped_ = true;
    return stopped_ || state_.aborted();
  }

  // Claims the next jobs; while none is claimable but other workers still
  // hold jobs in scope, waits for them (their jobs come back if they die).
  // False when nothing is left (or a stop was requested).
  bool Claim() {
    while (!Stopping()) {
      const auto jobs =
          queue_.ClaimJobs(config_, owner_, options_.claim_batch, options_.lease_s, options_.scope);
      if (!jobs.empty()) {
        for (const db::Job& job : jobs) {
          book_.Add(job.id);
          claimed_.push_back(job);
        }
        return true;
      }
      bool others_working = false;
      bool released = false;
      for (const std::string& owner : queue_.ReadLeaseOwners(config_, options_.scope)) {
        if (owner == owner_) continue;  // our own tests in flight
        if (IsDeadLocalOwner(owner)) {
          const std::int64_t count = queue_.ReleaseLeases(config_, owner);
          spdlog::warn("worker {} is gone: {} of its jobs go back to the queue", owner, count);
          report_.reclaimed += count;
          released = released || count > 0;
        } else {
          others_working = true;
        }
      }
      if (released) continue;
      if (!others_working) return false;
      // Nothing to compute here for a while: make our finished results
      // durable rather than keep them waiting for the next batch.
      writer_.RequestFlush();
      const auto wait_start = SteadyClock::now();
      while (!Stopping() && SecondsSince(wait_start) < options_.poll_interval_s)
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
  }

  std::shared_ptr<const engine::ArrayGeometry> Array(db::ArrayId id) {
    auto found = arrays_.find(id);
    if (found == arrays_.end()) {
      CachedArray cached;
      try {
        cached.geometry = std::make_shared<const engine::ArrayGeometry>(
            records::DecodeArrayRecord(catalogue_.ReadArray(id)));
      } catch (const InputError& error) {
        cached.error = error.what();
      }
      found = arrays_.emplace(id, std::move(cached)).first;
    }
    if (!found->second.error.empty()) throw InputError(found->second.error);
    return found->second.geometry;
  }

  struct CachedArray {
    std::shared_ptr<const engine::ArrayGeometry> geometry;
    std::string error;  // the array's decoding error, if any
  };

  db::Catalogue& catalogue_;  // inputs
  db::JobQueue queue_;        // on the catalogue the results go to
  db::ConfigId config_;
  std::string owner_;
  const RunOptions& options_;
  LeaseBook& book_;
  RunState& state_;
  ReadyQueue& ready_;
  ResultWriter& writer_;
  RunReport& report_;  // read_s, reclaimed: this thread's alone until Join
  const std::atomic<bool>* stop_;
  std::deque<db::Job> claimed_;
  std::map<db::ArrayId, CachedArray> arrays_;
  std::atomic<bool> stopped_{false};
  std::exception_ptr error_;
  std::thread thread_;  // last: started after every other member is ready
};

// The compute stage: the transform core, failures turned into records.
// The compute threads run a few steps of niceness below the reader and writer
// threads (jobs/README.md "Priorities"): with as many compute threads as
// cores, the writer would otherwise get only its share of a core, and a run
// that stores derived channels is bound by the writer. Lowered, the compute
// threads take every cycle the writer leaves idle and none it needs. Linux
// applies setpriority(PRIO_PROCESS, thread id) to that one thread. Raising a
// priority back needs privileges, so a thread stays lowered: the arena's
// workers only ever compute, and the calling thread, once it has computed,
// only waits for the reader and writer (started before, at normal priority)
// and reports. A failure leaves the thread as it was.
void LowerComputeThreadPriority() {
  constexpr int kNicenessStep = 5;
  thread_local bool lowered = false;
  if (lowered) return;
  lowered = true;
  const auto thread = static_cast<id_t>(syscall(SYS_gettid));
  errno = 0;
  const int niceness = getpriority(PRIO_PROCESS, thread);
  if (errno == 0) setpriority(PRIO_PROCESS, thread, std::min(niceness + kNicenessStep, 19));
}

void Compute(WorkItem& item, const engine::ProcessingConfig& config, bool store_kinematics,
             std::atomic<double>& compute_s) {
  LowerComputeThreadPriority();
  if (item.error) return;  // failed while reading
  const auto start = SteadyClock::now();
  try {
    item.processed = engine::ProcessTest(*item.array, item.signals, item.initial, config);
    // The verdict of engine/pipeline.h; a failed test's findings are stored
    // with its failure.
    if (const engine::Finding* failing = engine::FailingFinding(item.processed)) item.error = failing->detail;
  } catch (const InputError& error) {
    item.error = error.what();
  } catch (const std::exception& error) {
    // Not bad data but a failure all the same: record it and go on.
    item.error = std::string("processing failed: ") + error.what();
  }
  item.signals = {};  // the raw samples are not needed any more: free them before the write
  // Without derived channels to store, the writer needs only the summary:
  // free the series too, so a test waiting in the writer's batch holds a few
  // kilobytes instead of its whole kinematics.
  if (!store_kinematics) item.processed.kinematics = {};
  double seconds = SecondsSince(start);
  double total = compute_s.load();
  while (!compute_s.compare_exchange_weak(total, total + seconds)) {
  }
}

// Every test of a run allocates the same few megabytes of series (signals,
// kinematics, derived channels) and frees them a few milliseconds later.
// glibc's malloc would hand most of that back to the kernel on free (heap
// trimming above M_TRIM_THRESHOLD, and blocks above M_MMAP_THRESHOLD mapped
// and unmapped one by one), so the next test pays a page fault per 4 KiB
// page again: about 10 % of a test's CPU time in the profile. Keeping
// freed memory in the heap for reuse bounds the process at its largest
// working set, which the tokens of a run bound (jobs/README.md, "Memory").
void KeepFreedMemoryForReuse() {
#if defined(__GLIBC__)
  static const bool kept = [] {
    constexpr int kMmapThresholdBytes = 64 << 20;
    constexpr int kTrimThresholdBytes = 256 << 20;
    return mallopt(M_MMAP_THRESHOLD, kMmapThresholdBytes) == 1 &&
           mallopt(M_TRIM_THRESHOLD, kTrimThresholdBytes) == 1;
  }();
  if (!kept) spdlog::debug("run: malloc tuning (mallopt) not applied");
#endif
}

}  // namespace

void RunOptions::Check() const {
  auto require = [](bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("RunOptions: ") + what);
  };
  require(threads >= 0, "threads must be >= 0 (0 = all cores)");
  require(tests_in_flight_per_thread >= 1, "tests_in_flight_per_thread must be >= 1");
  require(claim_batch >= 1, "claim_batch must be >= 1");
  require(commit_batch >= 1, "commit_batch must be >= 1");
  require(commit_interval_s > 0.0, "commit_interval_s must be positive");
  require(lease_s > 0.0, "lease_s must be positive");
  require(poll_interval_s > 0.0, "poll_interval_s must be positive");
}

std::string MakeOwnerId() {
  std::random_device device;
  std::mt19937_64 generator((static_cast<std::uint64_t>(device()) << 32) ^ device());
  char suffix[17];
  std::snprintf(suffix, sizeof suffix, "%016llx", static_cast<unsigned long long>(generator()));
  return HostName() + ":" + std::to_string(getpid()) + ":" + suffix;
}

bool IsDeadLocalOwner(const std::string& owner) {
  const auto last = owner.rfind(':');
  if (last == std::string::npos || last == 0) return false;
  const auto middle = owner.rfind(':', last - 1);
  if (middle == std::string::npos) return false;
  if (owner.substr(0, middle) != HostName()) return false;
  const std::string pid_text = owner.substr(middle + 1, last - middle - 1);
  if (pid_text.empty() ||
      !std::all_of(pid_text.begin(), pid_text.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return false;
  const long pid = std::stol(pid_text);
  if (pid <= 0) return false;
  if (pid == getpid()) return !LiveOwners::Get().Contains(owner);
  return kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
}

RunReport RunScheduler(const std::string& db_path, const RunProcessing& processing, const RunOptions& options,
                       const ProgressCallback& progress, const std::atomic<bool>* stop) {
  options.Check();
  processing.config.Check();
  const auto start = SteadyClock::now();
  KeepFreedMemoryForReuse();

  RunReport report;
  report.owner = MakeOwnerId();
  const LiveOwnerScope live_owner(report.owner);
  report.threads = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
  report.max_tests_in_flight = report.threads * options.tests_in_flight_per_thread;

  db::CatalogueOptions catalogue_options;
  catalogue_options.durable = options.durable;
  // Jobs and results live in `work_path`: the catalogue, or a results file
  // beside the shared read-only catalogue (`inputs`).
  const bool results_file = !options.results_path.empty();
  const std::string& work_path = results_file ? options.results_path : db_path;
  std::optional<db::Catalogue> inputs;
  if (results_file) inputs.emplace(db::ResultsFile::OpenSharedCatalogue(db_path));
  db::Catalogue reader_catalogue = results_file ? db::ResultsFile::Open(work_path, *inputs, catalogue_options)
                                                : db::Catalogue::Open(db_path, catalogue_options);
  if (results_file) db::ResultsFile::CopyTests(*inputs, reader_catalogue, options.scope);
  db::JobQueue reader_queue(reader_catalogue);
  report.config = reader_catalogue.WriteConfig(processing.record);
  reader_queue.EnqueueMissing(report.config, options.scope, options.force, options.outdated);
  {
    const db::StatusCounts counts = reader_queue.ReadStatusCounts(report.config, options.scope);
    report.total = counts.pending + counts.running;
    report.skipped = counts.done;
  }
  spdlog::info("run {}: config '{}' ({}), {} tests to process, {} up to date, {} threads", report.owner,
               processing.record.name, processing.record.config_hash.substr(0, 12), report.total,
               report.skipped, report.threads);

  db::Catalogue writer_catalogue = db::Catalogue::Open(work_path, catalogue_options);
  LeaseBook book;
  RunState state(report.max_tests_in_flight);
  ReadyQueue ready;
  std::atomic<double> compute_s{0.0};
  std::exception_ptr error;
  {
    // Declared first, so it renews the leases until the writer has committed the last batch.
    Heartbeat heartbeat(work_path, catalogue_options, book, report.owner, options.lease_s);
    ResultWriter writer(writer_catalogue, report.config, engine::SolverName(processing.config.solver),
                        processing.config.storage.derived_channels, report.owner, options,
                        report.max_tests_in_flight, book, state, report, progress, start);
    JobReader reader(inputs ? *inputs : reader_catalogue, reader_catalogue, report.config, report.owner,
                     options, book, state, ready, writer, report, stop);
    const bool store_kinematics = options.store_kinematics &&
                                  processing.config.storage.derived_channels != engine::DerivedStorage::kNone;
    try {
      // The compute threads: an arena of exactly `threads`; reading and
      // writing happen on the two threads above, never on these.
      tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism,
                                      static_cast<std::size_t>(report.threads));
      tbb::task_arena arena(report.threads);
      arena.execute([&] {
        tbb::parallel_pipeline(
            static_cast<std::size_t>(report.max_tests_in_flight),
            tbb::make_filter<void, ItemPtr>(tbb::filter_mode::serial_in_order, [&](tbb::flow_control&
                                                                                       control) {
              ItemPtr item = ready.Pop();
              if (!item) control.stop();
              return item;
            }) & tbb::make_filter<ItemPtr, ItemPtr>(tbb::filter_mode::parallel, [&](ItemPtr item) {
              Compute(*item, processing.config, store_kinematics, compute_s);
              return item;
            }) & tbb::make_filter<ItemPtr, void>(tbb::filter_mode::serial_out_of_order, [&](ItemPtr item) {
              writer.Push(std::move(item));
            }));
      });
    } catch (...) {
      error = std::current_exception();
      state.Abort();
    }
    // The reader ends once the pipeline has (or on the abort); then the
    // writer commits what the pipeline handed it.
    const std::exception_ptr read_error = reader.Join();
    const std::exception_ptr write_error = writer.Join();
    if (!error) error = read_error ? read_error : write_error;
    report.stopped = reader.stopped();
  }
  if (error) {
    // Give our jobs back so another run need not wait for the leases.
    try {
      reader_queue.ReleaseLeases(report.config, report.owner);
    } catch (const std::exception& release_error) {
      // Not a second error line: the error rethrown below is what the user
      // acts on (a full disk fails this write too), and the leases expire
      // after lease_s anyway (or at once for the next run on this host).
      spdlog::debug("could not release the leases of {}: {}", report.owner, release_error.what());
    }
    std::rethrow_exception(error);
  }
  // Jobs claimed but never started (a stop) go back to the queue.
  report.released = reader_queue.ReleaseLeases(report.config, report.owner);
  report.peak_tests_in_memory = state.peak_in_memory();
  report.compute_s = compute_s.load();
  report.wall_s = SecondsSince(start);
  spdlog::info("run {}: {} done, {} failed, {} lost, {} released in {:.1f} s", report.owner, report.done,
               report.failed, report.lost, report.released, report.wall_s);
  return report;
}

}  // namespace napkin::jobs
