#include "jobs/watched_call.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>

namespace napkin::jobs {
namespace {

using std::chrono::milliseconds;

TEST(RunWatched, ReturnsWhenTheWorkIsDoneAndRethrowsWhatItThrew) {
  int computed = 0;
  RunWatched([&](const std::atomic<bool>&) { computed = 42; }, [] { return false; }, milliseconds(5));
  EXPECT_EQ(computed, 42);
  EXPECT_THROW(RunWatched([](const std::atomic<bool>&) { throw std::runtime_error("in the work"); },
                          [] { return false; }, milliseconds(5)),
               std::runtime_error);
}

TEST(RunWatched, AStopRequestCancelsTheWorkAndIsNotAskedAgain) {
  int asked = 0;
  bool saw_cancel = false;
  RunWatched(
      [&](const std::atomic<bool>& cancel) {
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
        while (!cancel.load() && std::chrono::steady_clock::now() < deadline)
          std::this_thread::sleep_for(milliseconds(1));
        saw_cancel = cancel.load();
      },
      [&] { return ++asked == 3; }, milliseconds(5));
  EXPECT_TRUE(saw_cancel);
  EXPECT_EQ(asked, 3);
}

// The point of the kept thread (jobs/watched_call.cpp): one call after another runs on the same
// thread, not on a new one each time.
TEST(RunWatched, CallsOneAfterAnotherRunOnOneKeptThread) {
  std::thread::id first;
  std::thread::id second;
  RunWatched([&](const std::atomic<bool>&) { first = std::this_thread::get_id(); }, [] { return false; },
             milliseconds(5));
  RunWatched([&](const std::atomic<bool>&) { second = std::this_thread::get_id(); }, [] { return false; },
             milliseconds(5));
  EXPECT_EQ(first, second);
  EXPECT_NE(first, std::this_thread::get_id());
}

// Two callers at once: the second, finding the kept thread busy, gets a thread of its own, so
// both works run together (each waits, at most 10 s, for the other to start).
TEST(RunWatched, CallsAtTheSameTimeRunTogether) {
  std::atomic<int> started{0};
  const auto work = [&](const std::atomic<bool>&) {
    ++started;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (started.load() < 2 && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(milliseconds(1));
  };
  bool together = false;
  std::thread other([&] {
    RunWatched(
        work, [] { return false; }, milliseconds(5));
  });
  RunWatched(
      work, [] { return false; }, milliseconds(5));
  together = started.load() == 2;
  other.join();
  EXPECT_TRUE(together);
}

// A child of fork() has no kept thread (threads do not survive a fork): it must not wait for one.
TEST(RunWatched, AForkedChildRunsItsOwnWork) {
  RunWatched([](const std::atomic<bool>&) {}, [] { return false; }, milliseconds(5));  // the parent's
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    int computed = 0;
    RunWatched([&](const std::atomic<bool>&) { computed = 7; }, [] { return false; }, milliseconds(5));
    ::_exit(computed == 7 ? 0 : 1);
  }
  int status = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (::waitpid(child, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      ::kill(child, SIGKILL);
      ::waitpid(child, &status, 0);
      FAIL() << "the forked child waited for its parent's kept thread";
    }
    std::this_thread::sleep_for(milliseconds(10));
  }
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
}

}  // namespace
}  // namespace napkin::jobs
