#include "ingest/temporary_folder.h"

#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <mutex>
#include <set>
#include <system_error>

#include "common/error.h"
#include "util/temporary_directory.h"

namespace napkin::ingest {
namespace fs = std::filesystem;

namespace {

constexpr std::array<int, 2> kSignals = {SIGINT, SIGTERM};

// The removals a signal carries out: one slot per live TemporaryFolder.
constexpr int kSlots = 16;
std::array<std::atomic<const TemporaryFolder::Removal*>, kSlots> g_removals{};
static_assert(std::atomic<const TemporaryFolder::Removal*>::is_always_lock_free, "read by a signal handler");
// The handlers running now, in any thread. A signal is delivered to any
// thread that does not block it (threads started later included), so a
// Removal taken out of g_removals is freed only once no handler runs: one
// that started before it was taken out may still be reading it
// (WaitForHandlers). A handler that starts after it was taken out reads the
// new one (sequentially consistent: the handler counts itself, then loads).
std::atomic<int> g_running_handlers{0};
static_assert(std::atomic<int>::is_always_lock_free, "changed by a signal handler");

// Installation of the handler (under g_mutex): the dispositions it replaced.
std::mutex g_mutex;
std::array<bool, kSlots> g_slot_taken{};
int g_live_folders = 0;
std::array<struct sigaction, kSignals.size()> g_previous{};
std::array<bool, kSignals.size()> g_installed{};

void RemoveTemporaryFoldersOnSignal(int signal_number) {
  const int saved_errno = errno;
  g_running_handlers.fetch_add(1);
  for (const auto& slot : g_removals) {
    const TemporaryFolder::Removal* removal = slot.load();
    if (removal == nullptr) continue;
    for (const std::string& file : removal->files) unlink(file.c_str());
    for (const std::string& folder : removal->folders) rmdir(folder.c_str());
  }
  g_running_handlers.fetch_sub(1);
  // Hand the signal on to the disposition before ours: raised now, it is
  // delivered when this handler returns (the signal is blocked meanwhile).
  for (std::size_t i = 0; i < kSignals.size(); ++i)
    if (kSignals[i] == signal_number && g_installed[i]) sigaction(signal_number, &g_previous[i], nullptr);
  raise(signal_number);
  errno = saved_errno;
}

// Returns once no signal handler runs in another thread: a Removal no longer
// published may then be freed. The calling thread blocks the signals (a
// handler of its own would have finished before this call resumed), and a
// handler only removes files, so the wait is short.
void WaitForHandlers() {
  while (g_running_handlers.load() != 0) sched_yield();
}

void InstallHandler() {
  for (std::size_t i = 0; i < kSignals.size(); ++i) {
    struct sigaction current {};
    sigaction(kSignals[i], nullptr, &current);
    // A signal ignored by whoever started napkin (e.g. SIGINT of a background job) stays ignored.
    g_installed[i] = current.sa_handler != SIG_IGN;
    if (!g_installed[i]) continue;
    struct sigaction action {};
    action.sa_handler = RemoveTemporaryFoldersOnSignal;
    sigemptyset(&action.sa_mask);
    for (const int other : kSignals) sigaddset(&action.sa_mask, other);
    sigaction(kSignals[i], &action, &g_previous[i]);
  }
}

void RestoreHandler() {
  for (std::size_t i = 0; i < kSignals.size(); ++i)
    if (g_installed[i]) sigaction(kSignals[i], &g_previous[i], nullptr);
  WaitForHandlers();  // one started before may still read g_installed and g_previous
  g_installed = {};
}

// SIGINT and SIGTERM held back in this thread while it lives, so that a
// folder never exists without its removal being published.
class BlockedSignals {
 public:
  BlockedSignals() {
    sigset_t blocked;
    sigemptyset(&blocked);
    for (const int signal_number : kSignals) sigaddset(&blocked, signal_number);
    pthread_sigmask(SIG_BLOCK, &blocked, &previous_);
  }
  ~BlockedSignals() { pthread_sigmask(SIG_SETMASK, &previous_, nullptr); }
  BlockedSignals(const BlockedSignals&) = delete;
  BlockedSignals& operator=(const BlockedSignals&) = delete;

 private:
  sigset_t previous_;
};

}  // namespace

TemporaryFolder::TemporaryFolder(const std::string& prefix, const std::string& purpose) {
  const BlockedSignals blocked;
  const fs::path directory = util::TemporaryDirectory();
  std::string pattern = (directory / (prefix + "XXXXXX")).string();
  if (mkdtemp(pattern.data()) == nullptr)
    throw InputError(purpose + ": cannot create a temporary folder in '" + directory.string() + "' (" +
                     std::generic_category().message(errno) + ").");
  path_ = pattern;
  {
    const std::lock_guard<std::mutex> lock(g_mutex);
    for (int slot = 0; slot < kSlots && slot_ < 0; ++slot)
      if (!g_slot_taken[static_cast<std::size_t>(slot)]) slot_ = slot;
    if (slot_ >= 0) {
      g_slot_taken[static_cast<std::size_t>(slot_)] = true;
      if (g_live_folders++ == 0) InstallHandler();
    }
  }
  Plan({});
}

void TemporaryFolder::Plan(const std::vector<std::string>& relative_files) {
  auto removal = std::make_unique<Removal>();
  std::set<std::string> folders;
  for (const std::string& relative : relative_files) {
    removal->files.push_back((path_ / relative).string());
    for (std::size_t slash = relative.find('/'); slash != std::string::npos;
         slash = relative.find('/', slash + 1))
      folders.insert(relative.substr(0, slash));
  }
  std::vector<std::string> deepest_first(folders.begin(), folders.end());
  std::stable_sort(deepest_first.begin(), deepest_first.end(),
                   [](const std::string& a, const std::string& b) {
                     return std::count(a.begin(), a.end(), '/') > std::count(b.begin(), b.end(), '/');
                   });
  for (const std::string& folder : deepest_first) removal->folders.push_back((path_ / folder).string());
  removal->folders.push_back(path_.string());
  Publish(std::move(removal));
}

void TemporaryFolder::Publish(std::unique_ptr<const Removal> removal) {
  if (slot_ < 0) return;         // more live folders than slots: removed on scope exit only
  const BlockedSignals blocked;  // no handler of this thread runs while the old one is freed
  g_removals[static_cast<std::size_t>(slot_)].store(removal.get());
  WaitForHandlers();  // nor one of another thread that may hold the old one
  removal_ = std::move(removal);
}

TemporaryFolder::~TemporaryFolder() {
  std::error_code ignored;
  fs::remove_all(path_, ignored);  // still published: a signal meanwhile finishes the removal
  if (slot_ < 0) return;
  const BlockedSignals blocked;
  g_removals[static_cast<std::size_t>(slot_)].store(nullptr);
  WaitForHandlers();  // removal_ is freed with this object
  const std::lock_guard<std::mutex> lock(g_mutex);
  g_slot_taken[static_cast<std::size_t>(slot_)] = false;
  if (--g_live_folders == 0) RestoreHandler();
}

}  // namespace napkin::ingest
