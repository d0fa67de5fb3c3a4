// `napkin merge SHARD.db...`: merge the shard catalogues of `run --shard I/N`
// (processed on other machines) into the --db catalogue.
#include <fmt/core.h>

#include <string>

#include "cli/catalogue_option.h"
#include "cli/command.h"
#include "cli/option_checks.h"

namespace napkin::cli {
namespace {

class MergeCommand : public Command {
 public:
  CLI::App* Setup(CLI::App& app, const GlobalOptions& global) override {
    global_ = &global;
    CLI::App* sub = app.add_subcommand("merge", "merge shard catalogues produced by `run --shard` into --db");
    sub->add_option("shards", shards_, "shard catalogue files")->required()->check(PathCheck("a shard path"));
    return sub;
  }

  int Run() override {
    // Catalogue::MergeShard refuses the catalogue's own file by any name.
    db::Catalogue catalogue = OpenCatalogue(*global_);
    // Each shard is merged in one transaction; a refused shard (conflict)
    // leaves the catalogue as the previous shards made it.
    for (const std::string& shard : shards_) {
      const db::MergeReport report = catalogue.MergeShard(shard);
      fmt::print("{}: {} tests added, {} results merged, {} failures merged, {} ratings merged{}\n", shard,
                 report.tests_added, report.results_merged, report.failures_merged, report.ratings_merged,
                 report.inbox_failures_merged > 0
                     ? fmt::format(", {} inbox failures merged", report.inbox_failures_merged)
                     : std::string());
    }
    return kExitOk;
  }

 private:
  const GlobalOptions* global_ = nullptr;
  std::vector<std::string> shards_;
};

}  // namespace

std::unique_ptr<Command> MakeMergeCommand() { return std::make_unique<MergeCommand>(); }

}  // namespace napkin::cli
