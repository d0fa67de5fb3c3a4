// `napkin query KIND` (the kinds of db/query_kinds.h): summaries across
// tests from the catalogue (each test's latest result, or the results of
// --config), filtered by --series, --variant and --where, ordered by --sort,
// cut by --limit (docs/formats.md "Query filters"), as an aligned table, CSV
// or JSON (one object per row, docs/formats.md field names).
#include <fmt/core.h>

#include <algorithm>

#include "app/query.h"
#include "app/table_output.h"
#include "cli/catalogue_option.h"
#include "cli/command.h"
#include "cli/option_checks.h"
#include "db/query_kinds.h"

namespace napkin::cli {
namespace {

// The row-selection options (app/query.h) on `command`.
void RegisterQueryFilters(CLI::App& command, app::QueryFilterOptions& filters) {
  command.add_option("--series", filters.tests.series, "only tests of this series (repeatable: any of them)")
      ->allow_extra_args(false);
  command
      .add_option("--variant", filters.tests.variants, "only tests of this variant (repeatable: any of them)")
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

// The help's list of the kinds, one line each: "  hic           HIC15, ...".
std::string KindsHelp() {
  std::size_t width = 0;
  for (const db::QueryKindSpec& kind : db::QueryKinds()) width = std::max(width, kind.name.size());
  std::string help = "Kinds:\n";
  for (const db::QueryKindSpec& kind : db::QueryKinds())
    help += fmt::format("  {:<{}}  {}\n", kind.name, width, kind.description);
  return help;
}

class QueryCommand : public Command {
 public:
  CLI::App* Setup(CLI::App& app, const GlobalOptions& global) override {
    global_ = &global;
    CLI::App* sub = app.add_subcommand("query", "summaries across tests");
    // An unknown kind is refused by the query layer (app::PrepareQuery), in the sentence the
    // service and the Python module give.
    sub->add_option("KIND", query_.kind, ChoiceList(db::QueryKindNames()))->required();
    sub->footer(KindsHelp());
    RegisterQueryFilters(*sub, query_.filters);
    sub->add_option("--limits", query_.limits,
                    "query limits: the limits each test is checked against, a limits preset (config/limits, "
                    "e.g. fmvss201u) or a JSON file")
        ->check(PathCheck("--limits"));
    sub->add_option("--format", format_, "table, csv or json")
        ->check(OneOfCheck("--format", {"table", "csv", "json"}))
        ->capture_default_str();
    return sub;
  }

  int Run() override {
    // The query is checked before the catalogue is opened (app/query.h).
    const app::PreparedQuery query = app::PrepareQuery(query_);
    db::Catalogue catalogue = OpenCatalogue(*global_, /*read_only=*/true);
    fmt::print("{}", app::FormatTable(app::RunQuery(catalogue, query), app::ParseTableFormat(format_)));
    return kExitOk;
  }

 private:
  const GlobalOptions* global_ = nullptr;
  app::Query query_;
  std::string format_ = "table";
};

}  // namespace

std::unique_ptr<Command> MakeQueryCommand() { return std::make_unique<QueryCommand>(); }

}  // namespace napkin::cli
