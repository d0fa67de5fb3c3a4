#include "serve/inbox.h"

#include <fcntl.h>
#include <poll.h>
#include <spdlog/spdlog.h>
#include <sys/inotify.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <functional>
#include <set>

#include "app/failure.h"
#include "common/error.h"
#include "db/catalogue.h"
#include "db/job_queue.h"
#include "formats/array_json.h"
#include "formats/channel_map.h"
#include "formats/json_file.h"
#include "ingest/discovery.h"
#include "ingest/import.h"
#include "jobs/scheduler.h"
#include "records/config_record.h"
#include "util/text.h"

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

// The bytes of sidecar `path`; nullopt when there is none. Judged on the
// descriptor opened (O_NONBLOCK: a FIFO never blocks the watcher): anything
// but a regular file of at most kMaxSidecarBytes is refused naming it, never
// skipped in favour of the sidecar above.
std::optional<std::string> ReadSidecarFile(const fs::path& path) {
  const std::string named = "sidecar '" + util::EscapeControl(path.string()) + "'";
  const formats::OpenedForReading file = formats::OpenForReading(path);
  if (file.error != 0) {
    const int error = file.error;
    struct stat link {};
    if (error == ENOENT && ::lstat(path.c_str(), &link) != 0) return std::nullopt;  // no sidecar here
    if (error == ENOENT)
      throw InputError(named + " is a symbolic link to nothing; point it at a JSON file or remove it.");
    if (error == ELOOP) throw InputError(named + " is a loop of symbolic links.");
    throw InputError(named + " cannot be opened (" + std::strerror(error) + ").");
  }
  const struct stat& status = file.status;
  if (!S_ISREG(status.st_mode))
    throw InputError(named + " is " + formats::FileTypeName(status.st_mode) +
                     ", not a regular file; a sidecar is a small JSON file.");
  if (static_cast<std::uintmax_t>(status.st_size) > kMaxSidecarBytes)
    throw InputError(named + " is " + std::to_string(status.st_size) + " bytes, more than the " +
                     std::to_string(kMaxSidecarBytes / 1024) + " KiB a sidecar may have.");
  return formats::ReadDescriptor(file.fd.get(), kMaxSidecarBytes, named, "a sidecar may have");
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
    const std::optional<std::string> text = ReadSidecarFile(path);
    if (!text) continue;
    const std::string named = "sidecar '" + util::EscapeControl(path.string()) + "'";
    Json json;
    try {
      json = Json::parse(*text);
    } catch (const Json::exception&) {
      throw InputError(named + " is not valid JSON.");
    }
    if (!json.is_object()) throw InputError(named + " is not a JSON object.");
    for (const auto& [key, value] : json.items()) {
      std::optional<std::string>* slot = key == "array"         ? &sidecar.array
                                         : key == "config"      ? &sidecar.config
                                         : key == "channel_map" ? &sidecar.channel_map
                                                                : nullptr;
      fs::path* from = key == "array"         ? &sidecar.array_file
                       : key == "config"      ? &sidecar.config_file
                       : key == "channel_map" ? &sidecar.channel_map_file
                                              : nullptr;
      if (!slot || !from)
        throw InputError(named + " has the unknown key '" + util::Abbreviated(key) + "'" +
                         " (it may give array, config and channel_map).");
      const std::string quoted_key = "'" + key + "'";
      if (!value.is_string() || value.get<std::string>().empty())
        throw InputError(named + " key " + quoted_key + " is not a non-empty text.");
      const std::string text_value = value.get<std::string>();
      if (text_value.size() > kMaxSidecarValueBytes)
        throw InputError(named + " key " + quoted_key + " is " + std::to_string(text_value.size()) +
                         " bytes long, more than the " + std::to_string(kMaxSidecarValueBytes) +
                         " a preset name or a file name may have.");
      if (util::HasControlCharacter(text_value))
        throw InputError(named + " key " + quoted_key + " holds a control character (" +
                         util::Quoted(text_value) + "); a preset name or a file name has none.");
      *slot = text_value;
      *from = path;
    }
  }
  return sidecar;
}

void CheckSidecarNames(const Sidecar& sidecar) {
  const auto check = [](const std::optional<std::string>& value, const fs::path& file, const char* key,
                        const std::function<void(const std::string&)>& load) {
    if (!value) return;
    try {
      load(*value);
    } catch (const InputError& bad) {
      throw InputError("sidecar '" + util::EscapeControl(file.string()) + "' key '" + key +
                       "': " + bad.what());
    } catch (const fs::filesystem_error& bad) {
      throw InputError("sidecar '" + util::EscapeControl(file.string()) + "' key '" + key + "' names " +
                       util::Quoted(*value) + ", which cannot be read (" + bad.code().message() + ").");
    }
  };
  check(sidecar.array, sidecar.array_file, "array",
        [](const std::string& name) { formats::LoadArray(name); });
  check(sidecar.channel_map, sidecar.channel_map_file, "channel_map",
        [](const std::string& name) { formats::LoadChannelMap(name); });
  check(sidecar.config, sidecar.config_file, "config",
        [](const std::string& name) { records::ResolveConfig(name); });
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
  const std::vector<SettledTest> settled = Settle(ScanInbox());
  if (settled.empty()) return;
  TestsToRun to_run;
  if (!ImportSettled(settled, to_run)) return;
  ProcessImported(to_run);
}

void Inbox::WatchFolder(const fs::path& folder) {
  if (inotify_fd_ >= 0)
    inotify_add_watch(
        inotify_fd_, folder.c_str(),
        IN_CREATE | IN_MODIFY | IN_CLOSE_WRITE | IN_MOVED_TO | IN_MOVED_FROM | IN_DELETE | IN_ATTRIB);
}

void Inbox::PassOver(const fs::path& path, const char* kind, const std::string& why,
                     std::set<fs::path>& excluded) {
  excluded.insert(path);
  const std::string sentence = "'" + util::EscapeControl(path.string()) + "' " + why;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!said_.insert(path.string() + "\n" + sentence).second) return;
  }
  spdlog::warn("{}", sentence);
  Record(kind, path.string(), "", sentence);
}

std::vector<Inbox::FoundTest> Inbox::ScanInbox() {
  const fs::path& inbox = options_.inbox;
  std::error_code error;
  // <inbox>/<series>/<variant>/...: the tests, and (inotify) a watch on every folder.
  WatchFolder(inbox);
  // What the inbox does not import is said once (log and status), and never imported: entries
  // that are not files or folders, files outside a variant folder, links to nothing, loops, and
  // links leading out of the inbox (refused: a test is read from the inbox only).
  const fs::path root = fs::weakly_canonical(inbox, error);
  std::set<fs::path> excluded;
  std::vector<fs::path> variants;
  for (fs::recursive_directory_iterator it(inbox, error), end; !error && it != end; it.increment(error)) {
    const fs::path path = it->path();
    const int depth = it.depth();
    std::error_code type_error;
    if (it->is_symlink(type_error)) {
      struct stat target {};
      if (::stat(path.c_str(), &target) != 0) {
        PassOver(path, "ignored",
                 errno == ELOOP ? "is a loop of symbolic links; it is ignored."
                                : "is a symbolic link to nothing; it is ignored.",
                 excluded);
        continue;
      }
      const fs::path resolved = fs::canonical(path, type_error);
      const std::string inside = root.string() + "/";
      if (type_error || !resolved.string().starts_with(inside)) {
        PassOver(path, "refused",
                 "is a symbolic link out of the inbox (to '" + util::EscapeControl(resolved.string()) +
                     "'); napkin serve reads tests from the inbox only, so it is not imported.",
                 excluded);
        continue;
      }
    }
    const bool folder = it->is_directory(type_error);
    const bool file = it->is_regular_file(type_error);
    if (!folder && !file) {
      struct stat status {};
      const mode_t mode = ::stat(path.c_str(), &status) == 0 ? status.st_mode : 0;
      PassOver(path, "ignored",
               std::string("is ") + formats::FileTypeName(mode) +
                   ", not a file or a folder; the inbox imports files and folders only, so it is ignored.",
               excluded);
      continue;
    }
    if (file && depth <= 1) {
      if (path.filename() == kSidecarName) continue;
      PassOver(path, "ignored",
               depth == 0
                   ? "is a file at the inbox root, where napkin serve looks for series folders only "
                     "(tests go in <inbox>/<series>/<variant>/); it is ignored."
                   : "is a file in series folder '" + util::EscapeControl(path.parent_path().string()) +
                         "', where napkin serve looks for variant folders only (tests go in "
                         "<inbox>/<series>/<variant>/); it is ignored.",
               excluded);
      continue;
    }
    if (!folder) continue;
    WatchFolder(path);
    if (depth == 1) variants.push_back(path);  // variant folders: <series>/<variant>
  }
  std::vector<FoundTest> found;
  for (const fs::path& variant : variants) {
    for (ingest::ImportInput& input : ingest::DiscoverInputs({variant.string()}).inputs) {
      // A test with a file passed over (a link out of the inbox, a FIFO) is not imported.
      bool passed_over = excluded.count(input.source) > 0;
      for (const fs::path& file : ingest::FilesOf(input))
        passed_over = passed_over || excluded.count(file) > 0;
      if (passed_over) continue;
      found.push_back({std::move(input), variant.parent_path().filename().string(),
                       variant.filename().string(), variant});
    }
  }
  return found;
}

std::vector<Inbox::SettledTest> Inbox::Settle(std::vector<FoundTest> found) {
  // Settled tests, each once per signature.
  const double now = Now();
  std::error_code error;
  std::vector<SettledTest> settled;
  std::lock_guard<std::mutex> lock(mutex_);
  std::set<std::string> seen;
  for (FoundTest& test : found) {
    const std::string key = test.input.source.string();
    seen.insert(key);
    const std::string signature = Signature(ingest::FilesOf(test.input), options_.inbox, test.folder);
    if (signature.empty()) continue;  // a file vanished while looking: next time
    const auto handled = handled_.find(key);
    if (handled != handled_.end() && handled->second == signature) continue;
    Pending& pending = pending_[key];
    if (pending.signature != signature) pending = Pending{signature, now};
    if (fs::exists(MarkerOf(test.input), error) || now - pending.since_s >= options_.settle_s) {
      pending.settled = true;
      settled.push_back({std::move(test), signature});
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
  return settled;
}

void Inbox::MarkHandled(const SettledTest& test) {
  // A test is tried once per signature, whatever the outcome.
  const std::string source = test.found.input.source.string();
  std::lock_guard<std::mutex> lock(mutex_);
  handled_[source] = test.signature;
  pending_.erase(source);
}

db::InboxFailure Inbox::FailureRecord(const char* kind, const SettledTest& settled,
                                      const std::string& sentence) {
  const FoundTest& test = settled.found;
  db::InboxFailure failure;
  failure.source = test.input.source.string();
  failure.test_name = test.input.name;
  failure.series = test.series;
  failure.variant = test.variant;
  failure.kind = kind;
  failure.error = sentence;
  failure.signature = settled.signature;
  return failure;
}

void Inbox::FailTest(db::Catalogue& catalogue, const char* kind, const SettledTest& settled,
                     const std::string& sentence) {
  const FoundTest& test = settled.found;
  // Recorded before it is said: a catalogue another process holds (db::DatabaseError) leaves
  // the test to be tried again in a second, and then it is said once.
  catalogue.WriteInboxFailure(FailureRecord(kind, settled, sentence));
  spdlog::error("{}", sentence);
  Record(kind, test.input.source.string(), test.input.name, sentence);
  std::lock_guard<std::mutex> lock(mutex_);
  ++failed_;
}

bool Inbox::ImportSettled(const std::vector<SettledTest>& settled, TestsToRun& to_run) {
  // Import each settled test, then process the imported ones (grouped by config).
  db::CatalogueOptions open;
  open.busy_timeout_ms = options_.busy_timeout_ms;
  open.check_integrity = true;
  // Checked once for the file the service writes (db::CatalogueOptions::integrity_checked_file):
  // quick_check reads all of it, which for every batch would cost more than the batch.
  open.integrity_checked_file = integrity_checked_file_;
  try {
    db::Catalogue catalogue = db::Catalogue::Open(options_.db_path, open);
    integrity_checked_file_ = catalogue.file_identity();
    const std::int64_t failed_earlier = failed_earlier_;
    for (const SettledTest& test : settled) {
      if (stop_) return false;
      ImportTest(catalogue, test, to_run);
      MarkHandled(test);
    }
    // The failures of before this start, said one line for all (their sentences were said then).
    if (const std::int64_t found = failed_earlier_ - failed_earlier; found > 0)
      spdlog::info(
          "{} inbox test(s) failed before with the same files and sidecars and are tried again when "
          "those change; `napkin status` lists them.",
          found);
  } catch (const db::DatabaseError&) {
    if (!WaitForCatalogue()) throw;
    return false;  // the tests not yet handled are tried again in a second
  }
  return true;
}

bool Inbox::WaitForCatalogue() {
  const app::Failure failure = app::DescribeFailure(std::current_exception(), options_.db_path);
  if (failure.category != app::FailureCategory::kCatalogueBusy) return false;
  spdlog::warn("{}", failure.sentence);
  std::lock_guard<std::mutex> lock(mutex_);
  waiting_ =
      "waiting for catalogue '" + options_.db_path + "', locked by another process: " + failure.sentence;
  return true;
}

void Inbox::ImportTest(db::Catalogue& catalogue, const SettledTest& settled, TestsToRun& to_run) {
  const FoundTest& test = settled.found;
  const std::string source = test.input.source.string();
  // Failed with these very files and sidecars before this start of the service: said then and
  // recorded in the catalogue (status lists it), not tried or said again until they change.
  if (const std::optional<db::InboxFailure> recorded = catalogue.ReadInboxFailure(source);
      recorded && recorded->signature == settled.signature) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++failed_earlier_;
    return;
  }
  // The folders give the series and the variant: their names are checked as folder names
  // here, not as the --series and --variant options import would name.
  try {
    util::CheckName("series folder name", test.series);
    util::CheckName("variant folder name", test.variant);
    if (test.variant == ingest::kNoVariantGroup)
      throw InputError(std::string("variant folder name '") + ingest::kNoVariantGroup +
                       "' is the name compare gives the tests without a variant; rename the folder.");
  } catch (const InputError& bad) {
    FailTest(catalogue, "folder", settled,
             "folder '" + util::EscapeControl(test.folder.string()) + "': " + bad.what() +
                 " Its tests are not imported.");
    return;
  }
  Sidecar sidecar;
  try {
    sidecar = ReadSidecars(options_.inbox, test.folder);
    // Without an array, the test's channel codes may define it (docs/serve.md "Sidecars").
    // Every name the sidecars give is resolved before anything is imported: a test is
    // never stored under a config that cannot run it, where it would wait forever.
    CheckSidecarNames(sidecar);
  } catch (const InputError& bad) {
    FailTest(catalogue, "sidecar", settled, bad.what());
    return;
  }
  try {
    ingest::ImportOptions import;
    import.array = sidecar.array.value_or("");
    import.array_option = "a napkin.json sidecar's \"array\" above '" + source + "'";
    import.series = test.series;
    import.variant = test.variant;
    if (sidecar.channel_map) import.channel_map = *sidecar.channel_map;
    // A recording that paused longer than --settle was imported half-written: its later
    // content replaces it (docs/serve.md "Inbox").
    import.supersede_changed_source = true;
    ingest::ImportReport report;
    try {
      report = ingest::ImportTests(catalogue, {source}, import);
    } catch (const InputError& bad) {  // options of all inputs: the sidecar's array or channel map
      FailTest(catalogue, "sidecar", settled,
               std::string(bad.what()) + " (from the sidecars above '" + source + "')");
      return;
    }
    SayImported(catalogue, settled, sidecar.config.value_or(""), report, to_run);
  } catch (const db::DatabaseError&) {
    throw;  // the catalogue's, not the test's: ImportSettled
  } catch (const std::exception&) {
    // Anything else is this test's failure, said once: it never stops the other tests.
    FailTest(catalogue, "import failed", settled,
             "test '" + source + "' could not be imported: " +
                 app::DescribeFailure(std::current_exception(), options_.db_path).sentence);
  }
}

void Inbox::SayImported(db::Catalogue& catalogue, const SettledTest& settled, const std::string& config,
                        const ingest::ImportReport& report, TestsToRun& to_run) {
  const FoundTest& test = settled.found;
  const std::string source = test.input.source.string();
  std::error_code error;
  // In the catalogue now (imported, or there already): an earlier failure of it is history.
  const bool in_catalogue = std::any_of(
      report.results.begin(), report.results.end(),
      [](const ingest::ImportResult& result) { return result.outcome != ingest::ImportOutcome::kFailed; });
  if (in_catalogue) catalogue.DeleteInboxFailure(source);
  // A file the importer could not read: recorded before anything is said or counted (FailTest).
  for (const ingest::ImportResult& result : report.results)
    if (result.outcome == ingest::ImportOutcome::kFailed && fs::exists(test.input.source, error))
      catalogue.WriteInboxFailure(FailureRecord("import failed", settled, result.message));
  for (const ingest::ImportResult& result : report.results) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (result.outcome == ingest::ImportOutcome::kImported) {
      ++imported_;
      if (result.superseded) ++superseded_;
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
    const char* kind = result.outcome == ingest::ImportOutcome::kImported
                           ? (result.superseded ? "superseded" : "imported")
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
    else if (result.superseded)
      spdlog::info("{}", message);
    else
      spdlog::info("{}: {} from {}", result.test_id, kind, source);
    Record(kind, source, result.test_id, message.empty() ? std::string(kind) : message);
  }
}

void Inbox::ProcessImported(const TestsToRun& to_run) {
  for (const auto& [config, ids] : to_run) {
    if (stop_) return;
    jobs::RunOptions run;
    run.scope.tests.external_ids = ids;
    run.threads = options_.threads;
    run.keep_freed_memory = false;  // a long-running process: memory goes back when idle
    try {
      // Checked with the sidecar before import; a config file changed since fails its tests.
      const records::ResolvedConfig processing = records::ResolveConfig(config);
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
      // Every test the run took is counted, the failed ones too (they were processed: their failure
      // is recorded), and the log says how many of each.
      const std::int64_t processed = report.done + report.failed;
      if (processed > 0)
        spdlog::info("processed {} from the inbox in {:.2f} s: {} with a result, {} failed",
                     processed == 1 ? std::string("1 test") : std::to_string(processed) + " tests",
                     report.wall_s, report.done, report.failed);
      for (const db::JobFailure& failure : counts.failures) {
        spdlog::error("test '{}' failed: {}", failure.test_id, failure.error);
        Record("failed", "", failure.test_id, failure.error);
      }
    } catch (const db::DatabaseError&) {
      if (!WaitForCatalogue()) throw;
    } catch (const InputError& bad) {
      for (const std::string& id : ids) {
        const std::string sentence = "test '" + id + "' was not processed: its processing config " +
                                     util::Quoted(config.empty() ? "default" : config) + ": " + bad.what();
        spdlog::error("{}", sentence);
        Record("failed", "", id, sentence);
      }
      std::lock_guard<std::mutex> lock(mutex_);
      failed_ += static_cast<std::int64_t>(ids.size());
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
              {"superseded", superseded_},
              {"skipped", skipped_},
              {"processed", processed_},
              {"failed", failed_},
              // Addition (issue 42): tests that failed with the same files before this start
              // (recorded in the catalogue: catalogue.inbox_failures), not tried again.
              {"failed_earlier", failed_earlier_},
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
