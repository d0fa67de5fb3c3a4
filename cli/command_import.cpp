// `napkin import`: tests of every input format (ingest/input_formats.h) into
// the catalogue, one transaction per test, idempotent by content
// hash. Exit 0 when every input was imported or already present, 3 when some
// inputs were refused but others stored (or already present), 1 when none
// could be stored.
#include <fmt/core.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>

#include "cli/catalogue_option.h"
#include "cli/command.h"
#include "cli/option_checks.h"
#include "cli/progress.h"
#include "cli/triple_option.h"
#include "ingest/import.h"
#include "ingest/input_formats.h"
#include "util/text.h"

namespace napkin::cli {
namespace {

class ImportCommand : public Command {
 public:
  CLI::App* Setup(CLI::App& app, const GlobalOptions& global) override {
    global_ = &global;
    CLI::App* sub = app.add_subcommand("import", "import " + ingest::FormatList("or"));
    sub->add_option("--array", options_.array,
                    "array preset name or array JSON file (the tests' geometry; default: the one each test's "
                    "channel codes define)")
        ->check(PathCheck("--array"));
    sub->add_option("--series", series_, "series the tests belong to");
    sub->add_option("--variant", variant_, "variant label (e.g. padding A)");
    sub->add_option("--test-id", test_id_, "test id (one test only; default: file or folder name)");
    AddTripleOption(sub, "--orientation", options_.orientation_rad,
                    "initial orientation PHI,THETA,PSI (rad)");
    AddTripleOption(sub, "--initial-velocity", options_.initial_velocity_mps,
                    "initial CG velocity VX,VY,VZ in the fixed frame (m/s)");
    sub->add_option("--channel-map", options_.channel_map,
                    "channel map preset or JSON file (inputs of channels with codes or SENATT/AXIS)")
        ->check(PathCheck("--channel-map"));
    sub->add_option("--column", options_.csv_columns,
                    "CSV column NAME feeds slot SLOT, as SLOT=NAME (repeatable)")
        ->allow_extra_args(false);
    sub->add_option("--position", position_,
                    "take only the dummy at this position (test object and position, e.g. 11)");
    sub->add_option("paths", paths_, "test files or folders")
        ->required()
        ->check(PathCheck("a path to import"));
    return sub;
  }

  int Run() override {
    if (!series_.empty()) options_.series = series_;
    if (!variant_.empty()) options_.variant = variant_;
    if (test_id_) options_.test_id = *test_id_;
    if (position_) options_.position = *position_;
    db::Catalogue catalogue = OpenCatalogue(*global_);

    std::unique_ptr<ProgressBar> progress_bar;
    const bool show_bar = ProgressBar::WantedOnStderr(global_->quiet);
    // Without a terminal, a log line every 10 s: tests done, rate and time left.
    ProgressLog progress_log("import", !global_->quiet && !StderrIsTerminal(), /*final_always=*/false);
    const auto start = std::chrono::steady_clock::now();
    std::int64_t failed = 0;
    const ingest::ImportProgress progress = [&](std::size_t done, std::size_t total,
                                                const ingest::ImportResult& result) {
      if (show_bar && !progress_bar) progress_bar = std::make_unique<ProgressBar>(total, true);
      if (result.outcome == ingest::ImportOutcome::kFailed) ++failed;
      const bool prints = !result.warnings.empty() || result.outcome != ingest::ImportOutcome::kImported;
      if (progress_bar && prints) progress_bar->Clear();
      for (const std::string& warning : result.warnings) spdlog::warn("{}", warning);
      if (result.outcome == ingest::ImportOutcome::kFailed) {
        spdlog::error("{}", result.message);
      } else if (result.outcome == ingest::ImportOutcome::kSkipped) {
        std::cout << util::EscapeControl(result.message) << "\n" << std::flush;
      }
      if (progress_bar) progress_bar->Update(done, result.test_id);
      progress_log.Update(static_cast<std::int64_t>(done), failed, static_cast<std::int64_t>(total),
                          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    };
    const ingest::ImportReport report = ingest::ImportTests(catalogue, paths_, options_, progress);
    progress_bar.reset();
    std::cout << report.SummaryLine() << "\n";
    if (report.failed == 0) return kExitOk;
    return report.imported + report.skipped > 0 ? kExitPartial : kExitFailure;
  }

 private:
  const GlobalOptions* global_ = nullptr;
  ingest::ImportOptions options_;
  std::string series_;
  std::string variant_;
  std::optional<std::string> test_id_;
  std::optional<std::string> position_;
  std::vector<std::string> paths_;
};

}  // namespace

std::unique_ptr<Command> MakeImportCommand() { return std::make_unique<ImportCommand>(); }

}  // namespace napkin::cli
