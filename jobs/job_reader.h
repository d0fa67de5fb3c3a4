#pragma once
// The reader thread of a run (jobs/README.md): claims jobs a few at a time
// under a lease and reads their tests ahead of the compute threads, one
// token per test.
#include <atomic>
#include <deque>
#include <exception>
#include <string>
#include <thread>

#include "jobs/result_writer.h"
#include "jobs/run_context.h"

namespace napkin::jobs {

class JobReader {
 public:
  // Claims in `jobs` (the work catalogue, on its own connection) and reads
  // the tests from `inputs` (the same connection, or the read-only catalogue
  // of a results-file run); pushes them to `ready`; asks `writer` to commit
  // early while it waits for other workers' jobs.
  JobReader(RunContext& context, db::Catalogue& inputs, db::Catalogue& jobs, ReadyQueue& ready,
            ResultWriter& writer);
  ~JobReader() { Join(); }
  JobReader(const JobReader&) = delete;
  JobReader& operator=(const JobReader&) = delete;

  // Waits for the thread (it ends when nothing is left to claim, on a stop
  // request or when the run aborts); returns its error, if any.
  std::exception_ptr Join();
  bool stopped() const { return stopped_; }

 private:
  void Loop();
  ItemPtr ReadNext();
  bool Stopping();
  bool Claim();

  RunContext& context_;  // the report's read_s, reclaimed: this thread's alone until Join
  records::TestInputReader inputs_;
  db::JobQueue queue_;  // on the catalogue the results go to
  ReadyQueue& ready_;
  ResultWriter& writer_;
  std::deque<db::Job> claimed_;
  std::atomic<bool> stopped_{false};
  std::exception_ptr error_;
  std::thread thread_;  // last: started after every other member is ready
};

}  // namespace napkin::jobs
