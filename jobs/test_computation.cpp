#include "jobs/test_computation.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <string>

#include "common/error.h"

namespace napkin::jobs {
namespace {

// The compute threads run 5 steps of niceness below the reader and writer
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

}  // namespace

void ComputeTest(WorkItem& item, RunContext& context) {
  LowerComputeThreadPriority();
  const engine::ProcessingConfig& config = context.processing.config;
  const auto start = SteadyClock::now();
  try {
    item.processed = context.options.compute(item.inputs, config);
    // The verdict of engine/pipeline.h; a failed test's findings are stored
    // with its failure.
    if (const engine::Finding* failing = engine::FailingFinding(item.processed)) item.error = failing->detail;
  } catch (const InputError& error) {
    // Bad data (an input, screening or plausibility error; common/error.h):
    // the test's failure. Anything else is no property of the test but a bug
    // in napkin (or no memory left): it leaves the pipeline and stops the
    // run, which commits what it computed, gives its leases back and
    // rethrows it, so the CLI reports an internal error (cli/diagnostics.h)
    // and the test is not marked failed for a fault of its own it does not have.
    item.error = error.what();
  }
  item.inputs.signals = {};  // the raw samples are not needed any more: free them before the write
  // Without derived channels to store, the writer needs only the summary:
  // free the series too, so a test waiting in the writer's batch holds a few
  // kilobytes instead of its whole kinematics.
  if (config.storage.derived_channels == engine::DerivedStorage::kNone) item.processed.kinematics = {};
  const double seconds = SecondsSince(start);
  double total = context.compute_s.load();
  while (!context.compute_s.compare_exchange_weak(total, total + seconds)) {
  }
}

}  // namespace napkin::jobs
