#pragma once
// The leases of a run (jobs/README.md "Leases"): the heartbeat thread that
// renews them, and the owner ids that tell a live worker from a dead one
// (MakeOwnerId, IsDeadLocalOwner in jobs/scheduler.h).
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

#include "jobs/run_context.h"

namespace napkin::jobs {

// Registers an owner id for the life of a scheduler: an owner with this
// process's pid that is not registered belonged to a dead process whose pid
// was reused (IsDeadLocalOwner).
class LiveOwnerScope {
 public:
  explicit LiveOwnerScope(std::string owner);
  ~LiveOwnerScope();
  LiveOwnerScope(const LiveOwnerScope&) = delete;
  LiveOwnerScope& operator=(const LiveOwnerScope&) = delete;

 private:
  std::string owner_;
};

// The heartbeat thread: renews the leases in the context's LeaseBook every
// lease_s / 4 on its own connection to the work catalogue, so a test that
// computes for long does not lose its job to another worker.
class LeaseKeeper {
 public:
  explicit LeaseKeeper(const RunContext& context);
  ~LeaseKeeper();
  LeaseKeeper(const LeaseKeeper&) = delete;
  LeaseKeeper& operator=(const LeaseKeeper&) = delete;

 private:
  void Loop();

  const RunContext& context_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread thread_;  // last: started after every other member is ready
};

}  // namespace napkin::jobs
