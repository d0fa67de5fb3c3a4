#pragma once
// The writer thread of a run (jobs/README.md): takes computed tests from a
// queue and commits them in batches on its own connection, one transaction
// per batch, each test's rows inside it all-or-nothing (a savepoint). The
// compute threads only append to the queue, so they go on computing while a
// batch commits.
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "jobs/run_context.h"

namespace napkin::jobs {

class ResultWriter {
 public:
  // Commits into `results` (the work catalogue: the jobs' states commit with
  // the results).
  ResultWriter(RunContext& context, db::Catalogue& results);
  ~ResultWriter() { Join(); }
  ResultWriter(const ResultWriter&) = delete;
  ResultWriter& operator=(const ResultWriter&) = delete;

  // A computed test (the pipeline's output filter). Never blocks for long:
  // the tokens bound the queue.
  void Push(ItemPtr item);
  // Commit what is queued now rather than wait for a full batch.
  void RequestFlush();
  // No more tests: commits the rest and ends the thread; returns the error
  // that stopped the commits, if any.
  std::exception_ptr Join();

 private:
  enum class Outcome { kDone, kFailed, kLost };
  struct Queued {
    ItemPtr item;
    SteadyClock::time_point arrived;
  };

  void Loop();
  void Commit(const std::vector<ItemPtr>& batch);

  RunContext& context_;  // the report's done, failed, lost, samples, write_s: this thread's alone until Join
  db::Catalogue& catalogue_;
  db::JobQueue queue_;  // on catalogue_
  std::size_t commit_target_;
  std::exception_ptr error_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Queued> queue_items_;
  bool flush_requested_ = false;
  bool closed_ = false;
  std::thread thread_;  // last: started after every other member is ready
};

}  // namespace napkin::jobs
