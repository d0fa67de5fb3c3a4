// `napkin status`: counts of the tests in the catalogue by state for a
// processing config, the results by napkin version and config, and the
// failures with their reasons (app/status.h reads them; the JSON is the
// service's too).
#include <fmt/core.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "app/status.h"
#include "cli/catalogue_option.h"
#include "cli/command.h"
#include "cli/option_checks.h"
#include "common/version.h"
#include "records/config_record.h"

namespace napkin::cli {
namespace {

// Results and failures by the napkin version that computed them, for every config
// (docs/formats.md "Version string"): what `run --outdated` would recompute.
void PrintVersionCounts(const std::vector<db::VersionCount>& counts) {
  if (counts.empty()) return;
  const std::string this_version = napkin::Version();
  std::vector<std::pair<std::string, std::string>> labels;  // version, config
  std::size_t version_width = 14;
  std::size_t config_width = 6;
  for (const db::VersionCount& count : counts) {
    std::string version = count.napkin_version.value_or("unknown (before version tracking)");
    if (count.napkin_version == this_version) version += " (this binary)";
    std::string config = count.config_name + " (" + count.config_hash.substr(0, 12) + ")";
    version_width = std::max(version_width, version.size());
    config_width = std::max(config_width, config.size());
    labels.emplace_back(std::move(version), std::move(config));
  }
  fmt::print("\n{:<{}}  {:<{}}  {:>8}  {:>8}\n", "napkin version", version_width, "config", config_width,
             "results", "failed");
  for (std::size_t i = 0; i < counts.size(); ++i)
    fmt::print("{:<{}}  {:<{}}  {:>8}  {:>8}\n", labels[i].first, version_width, labels[i].second,
               config_width, counts[i].results, counts[i].failed);
}

class StatusCommand : public Command {
 public:
  CLI::App* Setup(CLI::App& app, const GlobalOptions& global) override {
    global_ = &global;
    CLI::App* sub = app.add_subcommand("status", "counts of tests by state for the config, and the failures");
    sub->add_option("--config", config_, "processing config preset or JSON file (default: default)")
        ->check(PathCheck("--config"));
    sub->add_option("--format", format_, "table or json")
        ->check(OneOfCheck("--format", {"table", "json"}))
        ->capture_default_str();
    return sub;
  }

  int Run() override {
    const records::ResolvedConfig resolved = records::ResolveConfig(config_);
    db::Catalogue catalogue = OpenCatalogue(*global_, /*read_only=*/true);
    const app::CatalogueStatus status =
        app::ReadStatus(catalogue, resolved, /*with_versions=*/format_ == "table");
    if (format_ == "json") {
      // Stored error text that is not UTF-8 (an older napkin's): U+FFFD, never a failure.
      fmt::print("{}\n", app::StatusJson(status).dump(2, ' ', false,
                                                      nlohmann::ordered_json::error_handler_t::replace));
      return kExitOk;
    }
    const db::StatusCounts& counts = status.counts;
    fmt::print("catalogue  {}\nconfig     {} ({})\n\n", status.path, status.config_name,
               status.config_hash.substr(0, 12));
    fmt::print("{:<8} {:>8}\n", "tests", counts.tests);
    fmt::print("{:<8} {:>8}\n", "done", counts.done);
    fmt::print("{:<8} {:>8}\n", "failed", counts.failed);
    fmt::print("{:<8} {:>8}\n", "pending", counts.pending);
    fmt::print("{:<8} {:>8}\n", "running", counts.running);
    // Done tests whose result comes from salvaged channels (docs/algorithms.md "Faulty channels").
    if (counts.salvaged > 0) fmt::print("{:<8} {:>8}\n", "salvaged", counts.salvaged);
    PrintVersionCounts(status.versions);
    if (!counts.failures.empty()) {
      std::size_t width = 7;
      for (const db::JobFailure& failure : counts.failures) width = std::max(width, failure.test_id.size());
      fmt::print("\n{:<{}}  {}\n", "test_id", width, "error");
      for (const db::JobFailure& failure : counts.failures)
        fmt::print("{:<{}}  {}\n", failure.test_id, width, failure.error);
    }
    // Tests of `napkin serve --inbox` that never became tests of the catalogue (docs/serve.md "Inbox").
    if (!status.inbox_failures.empty()) {
      fmt::print("\ninbox tests that failed before their import: {}\n", status.inbox_failures.size());
      for (const db::InboxFailure& failure : status.inbox_failures)
        fmt::print("{}  {}\n", failure.source, failure.error);
    }
    return kExitOk;
  }

 private:
  const GlobalOptions* global_ = nullptr;
  std::string config_;
  std::string format_ = "table";
};

}  // namespace

std::unique_ptr<Command> MakeStatusCommand() { return std::make_unique<StatusCommand>(); }

}  // namespace napkin::cli
