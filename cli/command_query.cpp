// `napkin query {tests,hic,rotation,criteria,quality,conditioning}`: summaries across
// tests from the catalogue's query views (each test's latest result, or the
// results of --config), filtered by --series, --variant and --where, ordered
// by --sort, cut by --limit (docs/formats.md "Query filters"), as an aligned
// table, CSV or JSON (one object per row, docs/formats.md field names).
#include <fmt/core.h>

#include "cli/command.h"
#include "cli/db_option.h"
#include "cli/option_checks.h"
#include "cli/query_filters.h"
#include "cli/table_output.h"

namespace napkin::cli {
namespace {

class QueryCommand : public Command {
 public:
  CLI::App* Setup(CLI::App& app, const GlobalOptions& global) override {
    global_ = &global;
    CLI::App* sub = app.add_subcommand("query", "summaries across tests");
    std::vector<std::string> kinds;
    kinds.reserve(db::kQueryKindNames.size());
    for (const auto& [kind, name] : db::kQueryKindNames) kinds.emplace_back(name);
    sub->add_option("KIND", what_, "tests, hic, rotation, criteria, risk, quality or conditioning")
        ->required()
        ->check(OneOfCheck("the query KIND", kinds));
    filters_.Register(*sub);
    sub->add_option("--format", format_, "table, csv or json")
        ->check(OneOfCheck("--format", {"table", "csv", "json"}))
        ->capture_default_str();
    return sub;
  }

  int Run() override {
    const db::QueryKind kind = *engine::ParseName<db::QueryKind>(what_);
    db::QueryRequest request = filters_.Request(kind);
    db::Catalogue catalogue = OpenCatalogue(*global_, /*read_only=*/true);
    request.config = filters_.Config(catalogue);
    const db::Table table = catalogue.Query(kind, request);
    fmt::print("{}", FormatTable(table, ParseTableFormat(format_)));
    return kExitOk;
  }

 private:
  const GlobalOptions* global_ = nullptr;
  std::string what_;
  QueryFilterOptions filters_;
  std::string format_ = "table";
};

}  // namespace

std::unique_ptr<Command> MakeQueryCommand() { return std::make_unique<QueryCommand>(); }

}  // namespace napkin::cli
