// `napkin query {tests,hic,rotation,criteria,quality}`: summaries across
// tests from the catalogue's query views (each test's latest result), as an
// aligned table, CSV or JSON (one object per row, docs/formats.md field names).
#include <fmt/core.h>

#include <map>

#include "cli/catalogue_access.h"
#include "cli/command.h"
#include "cli/table_output.h"

namespace napkin::cli {
namespace {

const std::map<std::string, db::QueryKind>& Kinds() {
  static const std::map<std::string, db::QueryKind> kinds = {{"tests", db::QueryKind::kTests},
                                                             {"hic", db::QueryKind::kHic},
                                                             {"rotation", db::QueryKind::kRotation},
                                                             {"criteria", db::QueryKind::kCriteria},
                                                             {"quality", db::QueryKind::kQuality}};
  return kinds;
}

class QueryCommand : public Command {
 public:
  CLI::App* Setup(CLI::App& app, const GlobalOptions& global) override {
    global_ = &global;
    CLI::App* sub = app.add_subcommand("query", "summaries across tests");
    sub->add_option("what", what_, "tests, hic, rotation, criteria or quality")
        ->required()
        ->check(CLI::IsMember({"tests", "hic", "rotation", "criteria", "quality"}));
    sub->add_option("--series", series_, "only tests of this series");
    sub->add_option("--variant", variant_, "only tests of this variant");
    sub->add_option("--format", format_, "table, csv or json")
        ->check(CLI::IsMember({"table", "csv", "json"}))
        ->capture_default_str();
    return sub;
  }

  int Run() override {
    db::Catalogue catalogue = OpenCatalogue(*global_, /*read_only=*/true);
    db::TestFilter filter;
    filter.series = series_;
    filter.variant = variant_;
    const db::Table table = catalogue.Query(Kinds().at(what_), filter);
    fmt::print("{}", FormatTable(table, ParseTableFormat(format_)));
    return kExitOk;
  }

 private:
  const GlobalOptions* global_ = nullptr;
  std::string what_;
  std::optional<std::string> series_;
  std::optional<std::string> variant_;
  std::string format_ = "table";
};

}  // namespace

std::unique_ptr<Command> MakeQueryCommand() { return std::make_unique<QueryCommand>(); }

}  // namespace napkin::cli
