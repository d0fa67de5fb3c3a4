#include "jobs/watched_call.h"

#include <exception>
#include <future>
#include <thread>

namespace napkin::jobs {

void RunWatched(const std::function<void(const std::atomic<bool>& cancel)>& work,
                const std::function<bool()>& should_stop, std::chrono::milliseconds interval) {
  std::atomic<bool> cancel{false};
  std::promise<void> done;
  std::future<void> finished = done.get_future();
  std::thread worker([&] {
    try {
      work(cancel);
      done.set_value();
    } catch (...) {
      done.set_exception(std::current_exception());
    }
  });
  try {
    while (!cancel.load() && finished.wait_for(interval) != std::future_status::ready)
      if (should_stop()) cancel.store(true);
  } catch (...) {
    cancel.store(true);  // should_stop failed: stop the work before leaving
    worker.join();
    throw;
  }
  worker.join();
  finished.get();
}

}  // namespace napkin::jobs
