#pragma once
// The inbox of `napkin serve --inbox DIR` (docs/serve.md "Inbox"): every test
// that appears under <inbox>/<series>/<variant>/ (any format `napkin import`
// reads: ingest/input_formats.h) is imported
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
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "db/sqlite.h"
#include "ingest/import.h"
#include "ingest/input_formats.h"

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
  std::optional<std::string> array;   // array preset or JSON file (none: the channel codes'; docs/serve.md)
  std::optional<std::string> config;  // processing config preset or JSON file (default: default)
  std::optional<std::string> channel_map;  // channel map preset or JSON file
  // The sidecar file that gave each key: a name that leads nowhere is said naming it.
  std::filesystem::path array_file, config_file, channel_map_file;
};

// A sidecar is a small JSON object: anything larger is refused, not read.
inline constexpr std::size_t kMaxSidecarBytes = std::size_t{64} * 1024;
// A value names a preset or a file: at most a path's length.
inline constexpr std::size_t kMaxSidecarValueBytes = 4096;

// The sidecars of `folder` and every folder above it up to `inbox`, the
// nearest one's keys winning. Throws InputError naming the sidecar file for
// one that is not a regular file (a FIFO, a device, a folder, a link to one:
// judged on the opened descriptor, never read from), larger than
// kMaxSidecarBytes, not JSON, not an object, or has an unknown key or a
// value that is not a non-empty text of at most kMaxSidecarValueBytes
// without control characters.
Sidecar ReadSidecars(const std::filesystem::path& inbox, const std::filesystem::path& folder);

// Checks that the sidecars' array, channel map and processing config lead to
// a preset or a readable file; throws InputError naming the sidecar file
// that gave the one that does not.
void CheckSidecarNames(const Sidecar& sidecar);

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
  // A test found under <inbox>/<series>/<variant>/.
  struct FoundTest {
    ingest::ImportInput input;
    std::string series, variant;
    std::filesystem::path folder;  // <inbox>/<series>/<variant>
  };
  // A test due for import, with the signature of its files (Signature) it is tried for.
  struct SettledTest {
    FoundTest found;
    std::string signature;
  };
  using TestsToRun = std::map<std::string, std::vector<std::string>>;  // config -> test ids

  void Watch();
  // One look: ScanInbox, Settle, ImportSettled, ProcessImported.
  void LookAtInbox();
  // The tests under the inbox, each folder watched (inotify); what it does not import is said
  // once (PassOver) and left out, with the tests holding such a file.
  std::vector<FoundTest> ScanInbox();
  void WatchFolder(const std::filesystem::path& folder);
  void PassOver(const std::filesystem::path& path, const char* kind, const std::string& why,
                std::set<std::filesystem::path>& excluded);
  // The tests that have settled and were not tried with these files; the tests removed before
  // their import said.
  std::vector<SettledTest> Settle(std::vector<FoundTest> found);
  // Imports the settled tests into the catalogue, each marked handled (MarkHandled) once its
  // outcome is said, and adds those to process to `to_run`. False when the look ends here (a stop,
  // a catalogue another process holds locked: the tests left are tried again in a second); throws
  // the catalogue's other failures.
  bool ImportSettled(const std::vector<SettledTest>& settled, TestsToRun& to_run);
  // One test's import: its failure (folder names, sidecars, reading) said by FailTest; throws
  // db::DatabaseError only (the catalogue's, not the test's).
  // A test that failed with these files and sidecars before (db::InboxFailure, also before a
  // restart) is left alone.
  void ImportTest(db::Catalogue& catalogue, const SettledTest& settled, TestsToRun& to_run);
  // The import's results counted, said, and those to process added to `to_run`.
  void SayImported(db::Catalogue& catalogue, const SettledTest& settled, const std::string& config,
                   const ingest::ImportReport& report, TestsToRun& to_run);
  // The one place a test is marked tried for its signature (and no longer pending).
  void MarkHandled(const SettledTest& test);
  // A test that failed before it was imported: recorded in the catalogue (table
  // inbox_failures), then logged, recorded in the status and counted.
  void FailTest(db::Catalogue& catalogue, const char* kind, const SettledTest& settled,
                const std::string& sentence);
  static db::InboxFailure FailureRecord(const char* kind, const SettledTest& settled,
                                        const std::string& sentence);
  // In a catch of db::DatabaseError: true when the catalogue is locked by another process (the
  // status says why the inbox waits); false for another failure, which the caller throws on.
  bool WaitForCatalogue();
  // Runs the imported tests, config by config, with the run scheduler.
  void ProcessImported(const TestsToRun& to_run);
  void Record(const std::string& kind, const std::string& source, const std::string& test_id,
              const std::string& message);

  InboxOptions options_;
  // The catalogue file whose quick_check passed (watcher thread only).
  std::optional<db::FileIdentity> integrity_checked_file_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
  int inotify_fd_ = -1;

  mutable std::mutex mutex_;                    // guards everything below
  std::string mode_;                            // "inotify" or "poll"
  std::map<std::string, Pending> pending_;      // by source path: tests not yet settled
  std::map<std::string, std::string> handled_;  // source path -> signature tried
  std::optional<std::string> waiting_;          // the catalogue is locked: why we wait
  std::deque<nlohmann::ordered_json> events_;   // the last results and problems, newest last
  std::set<std::string> said_;                  // entries passed over (path and sentence): said once
  std::int64_t imported_ = 0, superseded_ = 0, skipped_ = 0, processed_ = 0, failed_ = 0;
  std::int64_t failed_earlier_ = 0;  // tests left alone: they failed with these files before this start
  double processing_s_ = 0.0;
};

}  // namespace napkin::serve
