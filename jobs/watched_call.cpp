#include "jobs/watched_call.h"

#include <unistd.h>

#include <condition_variable>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>

namespace napkin::jobs {
namespace {

// How one call ends: set by the thread that runs the work, awaited by the caller. Shared, so
// that neither side can outlive it.
struct CallState {
  std::mutex mutex;
  std::condition_variable ended;
  bool done = false;
  std::exception_ptr error;
};

// A thread kept for the work of RunWatched calls, one call at a time. A thread started for each
// call made every call pay for a fresh stack and a malloc arena whose memory glibc hands back
// to the system as the thread ends: the Python module's transform of a 10,000-sample test took
// 4 times as long as the same test in `napkin run` (bench/run_python.sh). Never destroyed: it
// waits for work until the process ends.
class KeptThread {
 public:
  KeptThread() : thread_([this] { Loop(); }) { thread_.detach(); }

  void Post(std::function<void()> task) {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      task_ = std::move(task);
    }
    posted_.notify_one();
  }

 private:
  void Loop() {
    for (;;) {
      std::function<void()> task;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        posted_.wait(lock, [this] { return static_cast<bool>(task_); });
        task = std::move(task_);
        task_ = nullptr;
      }
      task();
    }
  }

  std::mutex mutex_;
  std::condition_variable posted_;
  std::function<void()> task_;
  std::thread thread_;  // last: it starts once the members above exist
};

// The kept thread of this process (a child made by fork() has none: threads do not survive a
// fork, so it makes its own), claimed by one call at a time.
std::mutex kept_claim;
KeptThread* kept_thread = nullptr;
pid_t kept_pid = 0;

}  // namespace

void RunWatched(const std::function<void(const std::atomic<bool>& cancel)>& work,
                const std::function<bool()>& should_stop, std::chrono::milliseconds interval) {
  std::atomic<bool> cancel{false};
  const auto state = std::make_shared<CallState>();
  const auto run = [state, &work, &cancel] {
    std::exception_ptr error;
    try {
      work(cancel);
    } catch (...) {
      error = std::current_exception();
    }
    {
      const std::lock_guard<std::mutex> lock(state->mutex);
      state->error = error;
      state->done = true;
    }
    state->ended.notify_all();
  };
  // The kept thread when no other call has it (nor a fork() left its claim locked in this child);
  // else a thread of this call's own, as before.
  std::unique_lock<std::mutex> claim(kept_claim, std::try_to_lock);
  std::thread own;
  if (claim.owns_lock()) {
    if (kept_thread == nullptr || kept_pid != ::getpid()) {
      kept_thread = new KeptThread();  // the one of a parent process, if any, is gone with its thread
      kept_pid = ::getpid();
    }
    kept_thread->Post(run);
  } else {
    own = std::thread(run);
  }
  const auto wait_for_end = [&] {
    {
      std::unique_lock<std::mutex> lock(state->mutex);
      state->ended.wait(lock, [&] { return state->done; });
    }
    if (own.joinable()) own.join();
  };
  try {
    for (;;) {
      {
        std::unique_lock<std::mutex> lock(state->mutex);
        if (state->ended.wait_for(lock, interval, [&] { return state->done; })) break;
      }
      if (should_stop()) {
        cancel.store(true);
        break;
      }
    }
  } catch (...) {
    cancel.store(true);  // should_stop failed: stop the work before leaving
    wait_for_end();
    throw;
  }
  wait_for_end();
  if (state->error) std::rethrow_exception(state->error);
}

}  // namespace napkin::jobs
