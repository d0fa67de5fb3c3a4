// `napkin run`: process every test whose results are missing, failed or stale
// for the processing config, in parallel, resumably (jobs/scheduler.h).
#include <signal.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <charconv>
#include <filesystem>
#include <optional>

#include "app/db_protection.h"
#include "cli/catalogue_option.h"
#include "cli/command.h"
#include "cli/option_checks.h"
#include "cli/progress.h"
#include "common/error.h"
#include "db/results_file.h"
#include "formats/array_json.h"
#include "jobs/scheduler.h"
#include "records/config_record.h"
#include "util/output_destination.h"
#include "util/text.h"

namespace napkin::cli {
namespace {

// Set by SIGINT/SIGTERM; the scheduler stops claiming, commits the tests in
// flight and returns. A second signal kills as usual (SA_RESETHAND).
std::atomic<bool> g_stop_requested{false};
static_assert(std::atomic<bool>::is_always_lock_free, "set from a signal handler");

extern "C" void RequestStop(int) { g_stop_requested.store(true); }

void InstallStopHandlers() {
  struct sigaction action {};
  action.sa_handler = RequestStop;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

// "I/N" with 0 <= I < N.
std::optional<db::Shard> ParseShard(const std::string& text) {
  const auto slash = text.find('/');
  if (slash == std::string::npos) return std::nullopt;
  db::Shard shard;
  auto parse = [](std::string_view digits, int& value) {
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    return error == std::errc() && end == digits.data() + digits.size() && !digits.empty();
  };
  const std::string_view view(text);
  if (!parse(view.substr(0, slash), shard.index) || !parse(view.substr(slash + 1), shard.count))
    return std::nullopt;
  if (shard.count < 1 || shard.index < 0 || shard.index >= shard.count) return std::nullopt;
  return shard;
}

class RunCommand : public Command {
 public:
  CLI::App* Setup(CLI::App& app, const GlobalOptions& global) override {
    global_ = &global;
    CLI::App* sub = app.add_subcommand(
        "run", "process every test whose results are missing or stale for the config; resumable");
    sub->add_option("--series", series_, "only the tests of this series (repeatable: any of them)");
    sub->add_option("--test", test_ids_, "only this test (repeatable)");
    sub->add_option("--config", config_, "processing config preset or JSON file (default: default)")
        ->check(PathCheck("--config"));
    sub->add_option("--threads", options_.threads, "worker threads (default: all cores)")
        ->check(WholeNumberCheck("--threads", 1));
    sub->add_flag("--force", options_.force, "recompute tests whose results are up to date");
    sub->add_flag("--outdated", options_.outdated,
                  "also recompute results computed by another napkin version (see `napkin --version`)");
    sub->add_option("--shard", shard_, "process shard I of N (0 <= I < N) of the tests: I/N")
        ->check([](const std::string& text) {
          return ParseShard(text)
                     ? std::string()
                     : "--shard takes I/N with 0 <= I < N, e.g. 0/3; it is '" + util::Abbreviated(text) + "'";
        });
    sub->add_option("--results", options_.results_path,
                    "read --db only (shared, immutable) and write the results to this file (created if "
                    "missing; `napkin merge` takes it back)")
        ->check(PathCheck("--results"));
    return sub;
  }

  int Run() override {
    options_.scope.tests.series = series_;
    options_.scope.tests.external_ids = test_ids_;
    if (!shard_.empty()) options_.scope.shard = ParseShard(shard_);
    // The results file is a catalogue of its own, never the --db one's side
    // files (db::ResultsFile::Open refuses the catalogue itself).
    // Nor the --config file this command reads (docs/formats.md "Output destinations").
    app::ProtectInputFromOutput(records::ProcessingConfigPath(config_, formats::DefaultConfigDir()),
                                "the --config file");
    if (!options_.results_path.empty()) util::CheckNotProtected(options_.results_path);
    CheckScope();

    const records::ResolvedConfig processing = records::ResolveConfig(config_);
    InstallStopHandlers();
    RunProgressReporter reporter(global_->quiet);
    const jobs::RunReport report = jobs::RunScheduler(
        global_->db_path, processing, options_,
        [&](const jobs::RunProgress& progress) { reporter(progress); }, &g_stop_requested);
    reporter.Finish();

    const double processed = static_cast<double>(report.done + report.failed);
    if (!global_->quiet)
      spdlog::info(
          "{} tests done, {} failed, {} up to date; {:.1f} s, {:.2f} tests/s, {:.3g} samples/s (reading "
          "{:.1f} s, "
          "computing {:.1f} s over {} threads, writing {:.1f} s)",
          report.done, report.failed, report.skipped, report.wall_s,
          report.wall_s > 0 ? processed / report.wall_s : 0.0,
          report.wall_s > 0 ? static_cast<double>(report.samples) / report.wall_s : 0.0, report.read_s,
          report.compute_s, report.threads, report.write_s);
    if (report.stopped) {
      spdlog::error(
          "run stopped by a signal after committing the tests in flight; run it again to process the "
          "rest.");
      return kExitFailure;
    }
    if (report.failed > 0) {
      spdlog::error("{} tests failed; `napkin status` lists them with the reasons.", report.failed);
      return kExitPartial;
    }
    return kExitOk;
  }

 private:
  // Named series and tests must exist: a typo must not look like "nothing to do".
  void CheckScope() {
    if (!std::filesystem::exists(global_->db_path))
      throw InputError("catalogue '" + global_->db_path +
                       "' does not exist; create it with `napkin init`, `napkin import` or `napkin synth`.");
    // With --results the catalogue is never written (db/results_file.h).
    db::Catalogue catalogue = options_.results_path.empty()
                                  ? OpenCatalogue(*global_)
                                  : db::ResultsFile::OpenSharedCatalogue(global_->db_path);
    for (const std::string& series : series_)
      if (!catalogue.ReadSeries(series))
        throw InputError("series '" + series + "' is not in catalogue '" + catalogue.path() + "'.");
    for (const std::string& id : test_ids_)
      if (!catalogue.ExistsTestByExternalId(id))
        throw InputError("test '" + id + "' is not in catalogue '" + catalogue.path() + "'.");
  }

  const GlobalOptions* global_ = nullptr;
  jobs::RunOptions options_;
  std::vector<std::string> series_;
  std::vector<std::string> test_ids_;
  std::string config_;
  std::string shard_;
};

}  // namespace

std::unique_ptr<Command> MakeRunCommand() { return std::make_unique<RunCommand>(); }

}  // namespace napkin::cli
