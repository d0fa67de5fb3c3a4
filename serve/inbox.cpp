#include "serve/inbox.h"

#include <poll.h>
#include <spdlog/spdlog.h>
#include <sys/inotify.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>

#include "app/failure.h"
#include "common/error.h"
#include "db/catalogue.h"
#include "db/job_queue.h"
#include "ingest/discovery.h"
#include "ingest/import.h"
#include "jobs/scheduler.h"
#include "records/config_record.h"

namespace napkin::serve {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

constexpr const char* kSidecarName = "napkin.json";
constexpr const char* kMarkerSuffix = ".ready";
constexpr std::size_t kEventsKept = 50;
// With inotify, the inbox is still looked at this often (an event missed, a
// test waiting to settle is checked every second).
constexpr double kInotifyRescanS = 30.0;

double Now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

// The files of one test (an ISO-MME folder: all inside it).
std::vector<fs::path> FilesOf(const ingest::ImportInput& input) {
  if (input.format == ingest::InputFormat::kUds1992) return input.files;
  std::error_code error;
  if (!fs::is_directory(input.source, error)) return {input.source};
  std::vector<fs::path> files;
  for (fs::recursive_directory_iterator it(input.source, error), end; !error && it != end;
       it.increment(error))
    if (it->is_regular_file(error)) files.push_back(it->path());
  std::sort(files.begin(), files.end());
  return files;
}

// Sizes and modification times of the test's files and its sidecars: a test
// is tried again only when one of them changes. Empty when a file vanished.
std::string Signature(const std::vector<fs::path>& files, const fs::path& inbox, const fs::path& folder) {
  std::string signature;
  std::error_code error;
  const auto add = [&](const fs::path& file) {
    const auto size = fs::file_size(file, error);
    if (error) return false;
    const auto time = fs::last_write_time(file, error);
    if (error) return false;
    signature += file.string() + ":" + std::to_string(size) + ":" +
                 std::to_string(time.time_since_epoch().count()) + ";";
    return true;
  };
  for (const fs::path& file : files)
    if (!add(file)) return {};
  for (fs::path dir = folder;; dir = dir.parent_path()) {
    if (fs::exists(dir / kSidecarName, error)) add(dir / kSidecarName);
    if (dir == inbox || !dir.has_relative_path() || dir == dir.parent_path()) break;
  }
  return signature;
}

// The folder a test's marker stands in and the test's name: <folder>/<name>.ready.
fs::path MarkerOf(const ingest::ImportInput& input) {
  return input.source.parent_path() / (input.name + kMarkerSuffix);
}

// Whether test `test_id` has a result or a recorded failure under processing config `config`.
bool Finished(db::Catalogue& catalogue, const std::string& config, const std::string& test_id) {
  const std::optional<db::ConfigId> id =
      catalogue.FindConfigByHash(records::ResolveConfig(config).record.config_hash);
  if (!id) return false;
  db::JobScope scope;
  scope.tests.external_ids = {test_id};
  const db::StatusCounts counts = db::JobQueue(catalogue).ReadStatusCounts(*id, scope);
  return counts.done + counts.failed > 0;
}

}  // namespace

Sidecar ReadSidecars(const fs::path& inbox, const fs::path& folder) {
  std::vector<fs::path> chain;  // nearest first
  for (fs::path dir = folder;; dir = dir.parent_path()) {
    chain.push_back(dir);
    if (dir == inbox || dir == dir.parent_path()) break;
  }
  Sidecar sidecar;
  for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
    const fs::path path = *it / kSidecarName;
    std::error_code error;
    if (!fs::is_regular_file(path, error)) continue;
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    Json json;
    try {
      json = Json::parse(text.str());
    } catch (const Json::exception&) {
      throw InputError("sidecar '" + path.string() + "' is not valid JSON.");
    }
    if (!json.is_object()) throw InputError("sidecar '" + path.string() + "' is not a JSON object.");
    for (const auto& [key, value] : json.items()) {
      std::optional<std::string>* slot = key == "array"         ? &sidecar.array
                                         : key == "config"      ? &sidecar.config
                                         : key == "channel_map" ? &sidecar.channel_map
                                                                : nullptr;
      if (!slot)
        throw InputError("sidecar '" + path.string() + "' has the unknown key '" + key +
                         "' (it may give array, config and channel_map).");
      if (!value.is_string() || value.get<std::string>().empty())
        throw InputError("sidecar '" + path.string() + "' key '" + key + "' is not a non-empty text.");
      *slot = value.get<std::string>();
    }
  }
  return sidecar;
}

Inbox::Inbox(InboxOptions options) : options_(std::move(options)) {}

Inbox::~Inbox() { Stop(); }

void Inbox::Start() {
  std::error_code error;
  if (!fs::is_directory(options_.inbox, error))
    throw InputError("--inbox '" + options_.inbox.string() + "' is not a folder.");
  if (!options_.poll_s) {
    inotify_fd_ = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
    if (inotify_fd_ < 0)
      spdlog::warn("inotify is not available ({}); looking at the inbox every 2 s instead",
                   std::strerror(errno));
  }
  mode_ = inotify_fd_ >= 0 ? "inotify" : "poll";
  spdlog::info("watching inbox {} ({}{}; settled after {} s without change, or a <name>{} marker)",
               options_.inbox.string(), mode_,
               options_.poll_s ? ", every " + std::to_string(*options_.poll_s) + " s" : "", options_.settle_s,
               kMarkerSuffix);
  thread_ = std::thread([this] { Watch(); });
}

void Inbox::Stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  if (inotify_fd_ >= 0) close(inotify_fd_);
  inotify_fd_ = -1;
}

void Inbox::Watch() {
  const double poll_s = options_.poll_s.value_or(2.0);
  double next_look = 0;
  while (!stop_) {
    const double now = Now();
    if (now >= next_look) {
      try {
        LookAtInbox();
      } catch (...) {
        const app::Failure failure = app::DescribeFailure(std::current_exception(), options_.db_path);
        spdlog::error("{}", failure.sentence);
        Record("error", options_.inbox.string(), "", failure.sentence);
      }
      bool waiting = false;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        waiting = !pending_.empty() || waiting_.has_value();
      }
      // Tests waiting to settle (or a locked catalogue) are looked at every second.
      const double interval = inotify_fd_ >= 0 ? kInotifyRescanS : poll_s;
      next_look = Now() + (waiting ? std::min(1.0, interval) : interval);
    }
    if (inotify_fd_ >= 0) {
      pollfd fd{inotify_fd_, POLLIN, 0};
      const int wait_ms = static_cast<int>(std::clamp((next_look - Now()) * 1000.0, 0.0, 200.0));
      if (poll(&fd, 1, wait_ms) > 0) {
        alignas(inotify_event) char buffer[16384];
        while (read(inotify_fd_, buffer, sizeof buffer) > 0) {
        }
        next_look = std::min(next_look, Now());  // something changed: look now
      }
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  }
}

void Inbox::Record(const std::string& kind, const std::string& source, const std::string& test_id,
                   const std::string& message) {
  std::lock_guard<std::mutex> lock(mutex_);
  Json event = {{"time", Now()}, {"kind", kind}, {"source", source}};
  if (!test_id.empty()) event["test_id"] = test_id;
  event["message"] = message;
  events_.push_back(std::move(event));
  while (events_.size() > kEventsKept) events_.pop_front();
}

void Inbox::LookAtInbox() {
  const fs::path& inbox = options_.inbox;
  std::error_code error;
  // <inbox>/<series>/<variant>/...: the tests, and (inotify) a watch on every folder.
  struct Found {
    ingest::ImportInput input;
    std::string series, variant;
    fs::path folder;  // <inbox>/<series>/<variant>
  };
  std::vector<Found> found;
  if (inotify_fd_ >= 0)
    inotify_add_watch(
        inotify_fd_, inbox.c_str(),
        IN_CREATE | IN_MODIFY | IN_CLOSE_WRITE | IN_MOVED_TO | IN_MOVED_FROM | IN_DELETE | IN_ATTRIB);
  for (fs::recursive_directory_iterator it(inbox, error), end; !error && it != end; it.increment(error)) {
    std::error_code type_error;
    if (!it->is_directory(type_error)) continue;
    if (inotify_fd_ >= 0)
      inotify_add_watch(
          inotify_fd_, it->path().c_str(),
          IN_CREATE | IN_MODIFY | IN_CLOSE_WRITE | IN_MOVED_TO | IN_MOVED_FROM | IN_DELETE | IN_ATTRIB);
    if (it.depth() != 1) continue;  // variant folders: <series>/<variant>
    const fs::path variant = it->path();
    for (ingest::ImportInput& input : ingest::DiscoverInputs({variant.string()}).inputs)
      found.push_back({std::move(input), variant.parent_path().filename().string(),
                       variant.filename().string(), variant});
  }

  // Settled tests, each once per signature.
  const double now = Now();
  std::vector<std::pair<Found, std::string>> settled;  // with its signature
  {
    std::lock_guard<std::mutex> lock(mutex_);
    std::set<std::string> seen;
    for (Found& test : found) {
      const std::string key = test.input.source.string();
      seen.insert(key);
      const std::string signature = Signature(FilesOf(test.input), inbox, test.folder);
      if (signature.empty()) continue;  // a file vanished while looking: next time
      const auto handled = handled_.find(key);
      if (handled != handled_.end() && handled->second == signature) continue;
      Pending& pending = pending_[key];
      if (pending.signature != signature) pending = Pending{signature, now};
      if (fs::exists(MarkerOf(test.input), error) || now - pending.since_s >= options_.settle_s) {
        pending.settled = true;
        settled.emplace_back(std::move(test), signature);
      }
    }
    // A test that disappeared before it was imported (before it settled, or after, while the
    // catalogue was locked): said once, then forgotten.
    for (auto it = pending_.begin(); it != pending_.end();) {
      if (seen.count(it->first)) {
        ++it;
        continue;
      }
      const std::string sentence =
          "test '" + it->first + "' was removed from the inbox " +
          (it->second.settled ? "after it settled, before it could be imported" : "before it settled") +
          "; it was not imported.";
      spdlog::warn("{}", sentence);
      events_.push_back({{"time", now}, {"kind", "removed"}, {"source", it->first}, {"message", sentence}});
      it = pending_.erase(it);
    }
  }
  if (settled.empty()) return;

  // Import each settled test, then process the imported ones (grouped by config).
  db::CatalogueOptions open;
  open.busy_timeout_ms = options_.busy_timeout_ms;
  open.check_integrity = true;
  std::map<std::string, std::vector<std::string>> to_run;  // config -> test ids
  try {
    db::Catalogue catalogue = db::Catalogue::Open(options_.db_path, open);
    for (const auto& settled_test : settled) {
      const Found& test = settled_test.first;
      const std::string& signature = settled_test.second;
      if (stop_) return;
      const std::string source = test.input.source.string();
      const auto done = [&] {
        std::lock_guard<std::mutex> lock(mutex_);
        handled_[source] = signature;
        pending_.erase(source);
      };
      Sidecar sidecar;
      try {
        sidecar = ReadSidecars(inbox, test.folder);
        if (!sidecar.array)
          throw InputError("no napkin.json sidecar above '" + source +
                           "' gives its array (e.g. {\"array\": \"denton-3222\"}).");
      } catch (const InputError& bad) {
        spdlog::error("{}", bad.what());
        Record("sidecar", source, "", bad.what());
        std::lock_guard<std::mutex> lock(mutex_);
        ++failed_;
        handled_[source] = signature;
        pending_.erase(source);
        continue;
      }
      ingest::ImportOptions import;
      import.array = *sidecar.array;
      import.series = test.series;
      import.variant = test.variant;
      if (sidecar.channel_map) import.channel_map = *sidecar.channel_map;
      ingest::ImportReport report;
      try {
        report = ingest::ImportTests(catalogue, {source}, import);
      } catch (const InputError& bad) {  // options of all inputs: the sidecar's array or channel map
        const std::string sentence = std::string(bad.what()) + " (from the sidecars above '" + source + "')";
        spdlog::error("{}", sentence);
        Record("sidecar", source, "", sentence);
        std::lock_guard<std::mutex> lock(mutex_);
        ++failed_;
        handled_[source] = signature;
        pending_.erase(source);
        continue;
      }
      const std::string config = sidecar.config.value_or("");
      for (const ingest::ImportResult& result : report.results) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (result.outcome == ingest::ImportOutcome::kImported) {
          ++imported_;
          to_run[config].push_back(result.test_id);
        } else if (result.outcome == ingest::ImportOutcome::kSkipped) {
          ++skipped_;
          // Already in the catalogue: processed only when it has neither a result nor a failure
          // under its config (a restart after kill -9 between import and processing); a failure
          // is never retried.
          if (!Finished(catalogue, config, result.test_id)) to_run[config].push_back(result.test_id);
        } else {
          ++failed_;
        }
      }
      for (const ingest::ImportResult& result : report.results) {
        const char* kind = result.outcome == ingest::ImportOutcome::kImported  ? "imported"
                           : result.outcome == ingest::ImportOutcome::kSkipped ? "skipped"
                                                                               : "import failed";
        std::string message = result.message;
        // A test whose files went away while it was read: said as what happened, beside the
        // reader's own sentence.
        if (result.outcome == ingest::ImportOutcome::kFailed && !fs::exists(test.input.source, error)) {
          kind = "removed";
          message = "test '" + source +
                    "' was removed from the inbox while it was being imported; it was not imported (" +
                    result.message + ")";
        }
        if (result.outcome == ingest::ImportOutcome::kFailed)
          spdlog::error("{}", message);
        else
          spdlog::info("{}: {} from {}", result.test_id, kind, source);
        Record(kind, source, result.test_id, message.empty() ? std::string(kind) : message);
      }
      done();
    }
  } catch (const db::DatabaseError&) {
    const app::Failure failure = app::DescribeFailure(std::current_exception(), options_.db_path);
    if (failure.category != app::FailureCategory::kCatalogueBusy) throw;
    spdlog::warn("{}", failure.sentence);
    std::lock_guard<std::mutex> lock(mutex_);
    waiting_ =
        "waiting for catalogue '" + options_.db_path + "', locked by another process: " + failure.sentence;
    return;  // the tests not yet handled are tried again in a second
  }

  for (const auto& [config, ids] : to_run) {
    if (stop_) return;
    jobs::RunOptions run;
    run.scope.tests.external_ids = ids;
    run.threads = options_.threads;
    run.keep_freed_memory = false;  // a long-running process: memory goes back when idle
    const records::ResolvedConfig processing = records::ResolveConfig(config);
    try {
      const jobs::RunReport report = jobs::RunScheduler(options_.db_path, processing, run, {}, &stop_);
      db::CatalogueOptions read;
      read.read_only = true;
      db::Catalogue catalogue = db::Catalogue::Open(options_.db_path, read);
      db::JobScope scope;
      scope.tests.external_ids = ids;
      const db::StatusCounts counts = db::JobQueue(catalogue).ReadStatusCounts(report.config, scope);
      {
        std::lock_guard<std::mutex> lock(mutex_);
        waiting_.reset();
        processed_ += report.done;
        failed_ += report.failed;
        processing_s_ += report.wall_s;
      }
      if (report.done > 0)
        spdlog::info("processed {} tests from the inbox in {:.2f} s", report.done, report.wall_s);
      for (const db::JobFailure& failure : counts.failures) {
        spdlog::error("test '{}' failed: {}", failure.test_id, failure.error);
        Record("failed", "", failure.test_id, failure.error);
      }
    } catch (const db::DatabaseError&) {
      const app::Failure failure = app::DescribeFailure(std::current_exception(), options_.db_path);
      if (failure.category != app::FailureCategory::kCatalogueBusy) throw;
      std::lock_guard<std::mutex> lock(mutex_);
      waiting_ =
          "waiting for catalogue '" + options_.db_path + "', locked by another process: " + failure.sentence;
    }
  }
}

Json Inbox::Status() const {
  std::lock_guard<std::mutex> lock(mutex_);
  Json waiting_tests = Json::array();
  for (const auto& [source, pending] : pending_) waiting_tests.push_back(source);
  Json events = Json::array();
  for (const Json& event : events_) events.push_back(event);
  return Json{{"folder", options_.inbox.string()},
              {"watch", mode_},
              {"settle_s", options_.settle_s},
              {"catalogue_waiting", waiting_ ? Json(*waiting_) : Json(nullptr)},
              {"settling", std::move(waiting_tests)},
              {"imported", imported_},
              {"skipped", skipped_},
              {"processed", processed_},
              {"failed", failed_},
              {"events", std::move(events)}};
}

std::string Inbox::Metrics() const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto counter = [](const char* name, const char* help, const std::string& value, const char* type) {
    return std::string("# HELP ") + name + " " + help + "\n# TYPE " + name + " " + type + "\n" + name + " " +
           value + "\n";
  };
  return counter("napkin_inbox_imported_total", "Tests imported from the inbox.", std::to_string(imported_),
                 "counter") +
         counter("napkin_inbox_processed_total", "Inbox tests processed.", std::to_string(processed_),
                 "counter") +
         counter("napkin_inbox_failed_total", "Inbox tests that failed (sidecar, import or screening).",
                 std::to_string(failed_), "counter") +
         counter("napkin_inbox_queue_length", "Inbox tests waiting to settle.",
                 std::to_string(pending_.size()), "gauge") +
         counter("napkin_processing_seconds_total", "Time the run scheduler spent on inbox tests.",
                 std::to_string(processing_s_), "counter");
}

}  // namespace napkin::serve
