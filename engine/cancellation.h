#pragma once
// Stopping a computation early: the caller owns a std::atomic<bool> and sets
// it from elsewhere (a signal handler, another thread: the Python module on
// Ctrl-C, `napkin run` stopping); the engine only reads it, between the
// stages of ProcessTest and every kCancellationStride samples of its long
// loops, and throws Cancelled when it is set. Lock-free, so a signal handler
// may set it; a null pointer means "never cancelled". No I/O, no threads.
#include <Eigen/Core>
#include <atomic>
#include <stdexcept>

namespace napkin::engine {

// The computation was stopped because its cancellation flag was set: no
// result, and nothing about the test's input (not an InputError).
class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("the computation was cancelled.") {}
};

// Samples between two looks at the flag in a per-sample loop: a few
// microseconds of work, so a request is honoured within milliseconds while
// the relaxed load costs nothing measurable.
inline constexpr Eigen::Index kCancellationStride = 4096;

// Throws Cancelled when `cancel` is set.
inline void ThrowIfCancelled(const std::atomic<bool>* cancel) {
  if (cancel != nullptr && cancel->load(std::memory_order_relaxed)) throw Cancelled();
}

// In a loop over samples: looks at the flag every kCancellationStride samples.
inline void ThrowIfCancelled(const std::atomic<bool>* cancel, Eigen::Index sample) {
  if (sample % kCancellationStride == 0) ThrowIfCancelled(cancel);
}

// The same test without throwing, for code that must not throw: GCC takes a
// target_clones function for one that cannot throw, and an exception leaving one
// ends the process in std::terminate (engine/cfc_filter.cpp).
inline bool IsCancelled(const std::atomic<bool>* cancel, Eigen::Index sample) {
  return sample % kCancellationStride == 0 && cancel != nullptr && cancel->load(std::memory_order_relaxed);
}

}  // namespace napkin::engine
