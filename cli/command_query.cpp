// `napkin query {tests,hic,rotation,criteria,risk,quality,conditioning,limits}`: summaries across
// tests from the catalogue's query views (each test's latest result, or the
// results of --config), filtered by --series, --variant and --where, ordered
// by --sort, cut by --limit (docs/formats.md "Query filters"), as an aligned
// table, CSV or JSON (one object per row, docs/formats.md field names).
#include <fmt/core.h>

#include "app/limits.h"
#include "app/query.h"
#include "app/table_output.h"
#include "cli/catalogue_option.h"
#include "cli/command.h"
#include "cli/option_checks.h"
#include "common/error.h"
#include "common/joined.h"

namespace napkin::cli {
namespace {

// The row-selection options (app/query.h) on `command`.
void RegisterQueryFilters(CLI::App& command, app::QueryFilterOptions& filters) {
  command.add_option("--series", filters.series, "only tests of this series (repeatable: any of them)")
      ->allow_extra_args(false);
  command.add_option("--variant", filters.variants, "only tests of this variant (repeatable: any of them)")
      ->allow_extra_args(false);
  command
      .add_option(
          "--where", filters.where,
          "only rows where EXPR holds, e.g. \"hic15>700 and variant=foam-a\" (repeatable: all of them)")
      ->allow_extra_args(false);
  command.add_option("--sort", filters.sort, "order by FIELD[:desc] (repeatable; ties: by test_id)")
      ->allow_extra_args(false);
  command.add_option("--limit", filters.limit, "at most N rows");
  command.add_option("--config", filters.config,
                     "results of this processing config (name or hash prefix; default: each test's latest)");
}

class QueryCommand : public Command {
 public:
  CLI::App* Setup(CLI::App& app, const GlobalOptions& global) override {
    global_ = &global;
    CLI::App* sub = app.add_subcommand("query", "summaries across tests");
    std::vector<std::string> kinds;
    kinds.reserve(db::kQueryKindNames.size());
    for (const auto& [kind, name] : db::kQueryKindNames) kinds.emplace_back(name);
    kinds.emplace_back("limits");  // `query criteria` against --limits (cli/limits.h)
    sub->add_option("KIND", what_, "tests, hic, rotation, criteria, risk, quality, conditioning or limits")
        ->required()
        ->check(OneOfCheck("the query KIND", kinds));
    RegisterQueryFilters(*sub, filters_);
    sub->add_option("--limits", limits_,
                    "query limits: the limits each test is checked against, a limits preset (config/limits, "
                    "e.g. fmvss201u) or a JSON file")
        ->check(PathCheck("--limits"));
    sub->add_option("--format", format_, "table, csv or json")
        ->check(OneOfCheck("--format", {"table", "csv", "json"}))
        ->capture_default_str();
    return sub;
  }

  int Run() override {
    const bool limits = what_ == "limits";
    if (limits && !limits_)
      throw UsageError("`napkin query limits` needs --limits NAME (presets: " + Joined(app::LimitPresets()) +
                       ").");
    if (!limits && limits_) throw UsageError("--limits applies to `napkin query limits` only.");
    const std::optional<app::LimitSet> limit_set =
        limits ? std::optional<app::LimitSet>(app::LoadLimits(*limits_)) : std::nullopt;
    // query limits: the rows of query criteria, filtered and sorted as it does, each against each limit.
    const db::QueryKind kind = limits ? db::QueryKind::kCriteria : *engine::ParseName<db::QueryKind>(what_);
    db::QueryRequest request = filters_.Request(kind);
    db::Catalogue catalogue = OpenCatalogue(*global_, /*read_only=*/true);
    request.config = filters_.Config(catalogue);
    const db::Table table = catalogue.Query(kind, request);
    fmt::print("{}", app::FormatTable(limits ? app::LimitsTable(table, *limit_set) : table,
                                      app::ParseTableFormat(format_)));
    return kExitOk;
  }

 private:
  const GlobalOptions* global_ = nullptr;
  std::string what_;
  app::QueryFilterOptions filters_;
  std::string format_ = "table";
  std::optional<std::string> limits_;
};

}  // namespace

std::unique_ptr<Command> MakeQueryCommand() { return std::make_unique<QueryCommand>(); }

}  // namespace napkin::cli
