#pragma once
// The inbox of `napkin serve --inbox DIR` (docs/serve.md "Inbox"): every test
// that appears under <inbox>/<series>/<variant>/ (what `napkin import` reads:
// a CSV file, an ISO-MME folder, a UDS-1992 group, a zip archive) is imported
// once it has settled and processed at once with the run scheduler
// (jobs::RunScheduler), array and options from the napkin.json sidecars of
// the folders above it. The inbox is only read, never changed.
//
// One watcher thread: it wakes on inotify events (or every --poll interval),
// looks at the inbox, and imports and processes what has settled. A test is
// settled when its files' sizes and modification times have not changed for
// --settle seconds, or when a marker file <name>.ready stands beside it. A
// test is tried once per content: a test already in the catalogue (same
// content hash) is skipped, a failure (import or screening) is recorded and
// shown in the status, never retried while its files stay as they are.
#include <atomic>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace napkin::serve {

struct InboxOptions {
  std::string db_path;
  std::filesystem::path inbox;
  double settle_s = 5.0;
  // Set: look at the inbox every poll_s seconds (network file systems, where
  // inotify sees nothing); unset: inotify.
  std::optional<double> poll_s;
  int threads = 0;  // processing threads of the run scheduler; 0: all cores
  // How long an import waits for a catalogue another process holds; then it
  // says so in the status and tries again.
  int busy_timeout_ms = 5000;
};

// What a sidecar (napkin.json) gives the tests below it (docs/serve.md "Sidecars").
struct Sidecar {
  std::optional<std::string> array;        // array preset or JSON file (required for import)
  std::optional<std::string> config;       // processing config preset or JSON file (default: default)
  std::optional<std::string> channel_map;  // channel map preset or JSON file
};

// The sidecars of `folder` and every folder above it up to `inbox`, the
// nearest one's keys winning. Throws InputError naming the sidecar file for
// one that is not JSON, not an object, has an unknown key or a key that is not text.
Sidecar ReadSidecars(const std::filesystem::path& inbox, const std::filesystem::path& folder);

class Inbox {
 public:
  explicit Inbox(InboxOptions options);
  ~Inbox();
  Inbox(const Inbox&) = delete;
  Inbox& operator=(const Inbox&) = delete;

  // Starts the watcher thread. Throws InputError when the inbox is not a readable folder.
  void Start();
  // Asks the watcher to stop: a run in progress finishes the tests in flight
  // and releases the others' leases (jobs::RunScheduler's stop); joins it.
  void Stop();

  // "inbox" of GET /api/v1/status: the folder, the way it is watched, the
  // tests waiting to settle, counts, the last results and the problems.
  nlohmann::ordered_json Status() const;
  // The inbox's lines of GET /metrics (Prometheus text).
  std::string Metrics() const;

 private:
  // A test seen but not yet tried: its files' signature and since when it has held.
  struct Pending {
    std::string signature;
    double since_s = 0;
    bool settled = false;  // due for import (it waits only for the catalogue)
  };
  void Watch();
  void LookAtInbox();
  void Record(const std::string& kind, const std::string& source, const std::string& test_id,
              const std::string& message);

  InboxOptions options_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
  int inotify_fd_ = -1;

  mutable std::mutex mutex_;                    // guards everything below
  std::string mode_;                            // "inotify" or "poll"
  std::map<std::string, Pending> pending_;      // by source path: tests not yet settled
  std::map<std::string, std::string> handled_;  // source path -> signature tried
  std::optional<std::string> waiting_;          // the catalogue is locked: why we wait
  std::deque<nlohmann::ordered_json> events_;   // the last results and problems, newest last
  std::int64_t imported_ = 0, skipped_ = 0, processed_ = 0, failed_ = 0;
  double processing_s_ = 0.0;
};

}  // namespace napkin::serve
