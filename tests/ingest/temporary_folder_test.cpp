// ingest::TemporaryFolder's signal handler (issue 29 point 19): what it
// reads stays valid whichever thread the signal is delivered to. A thread
// started after the folder was made takes the signal, and while its
// handler removes the planned files the folder's owner replaces the plan:
// the handler must never read the plan being freed (AddressSanitizer reports
// a heap-use-after-free if it does), and it removes the folder.
#include "ingest/temporary_folder.h"

#include <gtest/gtest.h>
#include <pthread.h>
#include <signal.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

namespace napkin::ingest {
namespace {

namespace fs = std::filesystem;

std::atomic<int> g_passed_on{0};

// The disposition before TemporaryFolder's, to which its handler hands the signal on.
void CountSignal(int) { g_passed_on.fetch_add(1); }

TEST(TemporaryFolderSignals, ASignalToAnotherThreadNeverReadsAFreedPlan) {
  struct sigaction counting {};
  counting.sa_handler = CountSignal;
  sigemptyset(&counting.sa_mask);
  struct sigaction before {};
  ASSERT_EQ(sigaction(SIGTERM, &counting, &before), 0);

  // This thread never takes SIGTERM: the signal goes to the other one.
  sigset_t term;
  sigemptyset(&term);
  sigaddset(&term, SIGTERM);
  sigset_t mask_before;
  ASSERT_EQ(pthread_sigmask(SIG_BLOCK, &term, &mask_before), 0);

  fs::path folder;
  {
    TemporaryFolder temporary("napkin-signal-test-", "the test");
    folder = temporary.path();
    // Many files: the handler takes a while to remove them, in order.
    std::vector<std::string> files;
    fs::create_directory(folder / "sub");
    for (int i = 0; i < 5000; ++i) {
      files.push_back("sub/file-" + std::to_string(i) + ".txt");
      std::ofstream(folder / files.back()) << i;
    }
    temporary.Plan(files);

    std::atomic<bool> ready{false};
    std::thread receiver([&] {
      // The signal is handled on this thread (started after the folder was made).
      pthread_sigmask(SIG_UNBLOCK, &term, nullptr);
      ready = true;
      while (g_passed_on.load() == 0) std::this_thread::yield();
    });
    while (!ready) std::this_thread::yield();
    ASSERT_EQ(pthread_kill(receiver.native_handle(), SIGTERM), 0);
    // Once the handler is at work on the plan (its first file is gone), the
    // owner replaces the plan by a small one, freeing the one the handler reads.
    while (fs::exists(folder / files.front()) && g_passed_on.load() == 0) {
    }
    int replans = 0;
    while (g_passed_on.load() == 0) {
      temporary.Plan({"other.txt"});
      ++replans;
    }
    receiver.join();
    EXPECT_GE(replans, 1);
    EXPECT_FALSE(fs::exists(folder)) << "the handler did not remove " << folder;
  }
  EXPECT_EQ(g_passed_on.load(), 1);
  pthread_sigmask(SIG_SETMASK, &mask_before, nullptr);
  sigaction(SIGTERM, &before, nullptr);
}

}  // namespace
}  // namespace napkin::ingest
