#pragma once
// Work that can be stopped from the thread that asked for it: the Python
// module's transform (python/) computes a test on a thread of its own while
// the interpreter's main thread, which alone runs Python's signal handlers,
// looks for Ctrl-C. The engine has no threads; this is where they are.
#include <atomic>
#include <chrono>
#include <functional>

namespace napkin::jobs {

// Runs `work(cancel)` on another thread (one kept for these calls, or one of
// its own while another call has that) while the calling thread calls
// `should_stop()` every `interval`. Once it returns true, `cancel` is set and
// the call waits for `work` to return (the engine reads `cancel` and throws
// engine::Cancelled within milliseconds); `should_stop` is not called again.
// Returns when `work` has returned, rethrowing what it threw, so nothing
// `work` uses is released before it has stopped.
void RunWatched(const std::function<void(const std::atomic<bool>& cancel)>& work,
                const std::function<bool()>& should_stop, std::chrono::milliseconds interval);

}  // namespace napkin::jobs
