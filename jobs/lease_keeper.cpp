#include "jobs/lease_keeper.h"

#include <signal.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <optional>
#include <random>
#include <set>

namespace napkin::jobs {
namespace {

std::string HostName() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "localhost";
  return name;
}

// Owner ids of the schedulers running in this process.
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

}  // namespace

LiveOwnerScope::LiveOwnerScope(std::string owner) : owner_(std::move(owner)) {
  LiveOwners::Get().Add(owner_);
}

LiveOwnerScope::~LiveOwnerScope() { LiveOwners::Get().Remove(owner_); }

LeaseKeeper::LeaseKeeper(const RunContext& context) : context_(context), thread_([this] { Loop(); }) {}

LeaseKeeper::~LeaseKeeper() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void LeaseKeeper::Loop() {
  try {
    std::optional<db::Catalogue> catalogue;
    const double lease_s = context_.options.lease_s;
    const auto period = std::chrono::duration<double>(lease_s / 4.0);
    std::unique_lock lock(mutex_);
    while (!wake_.wait_for(lock, period, [this] { return stopping_; })) {
      lock.unlock();
      if (!catalogue) catalogue.emplace(db::Catalogue::Open(context_.work_path));
      db::JobQueue queue(*catalogue);
      // A job committed between the snapshot and its renewal is simply
      // not renewed (RenewLease is false for a job no longer running).
      for (const db::JobId job : context_.leases.Snapshot())
        queue.RenewLease(job, context_.report.owner, lease_s);
      lock.lock();
    }
  } catch (const std::exception& error) {
    // The run goes on; its leases may then expire and its results be
    // dropped as lost (never stored twice).
    spdlog::error("lease renewal stopped: {}", error.what());
  }
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

}  // namespace napkin::jobs
