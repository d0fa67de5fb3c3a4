// `napkin report`: one self-contained HTML file of the selected tests
// (cli/report_builder.h; docs/formats.md "HTML report").
#include <fmt/core.h>

#include <string>

#include "cli/command.h"
#include "cli/report_builder.h"
#include "util/output_destination.h"

namespace napkin::cli {
namespace {

class ReportCommand : public Command {
 public:
  CLI::App* Setup(CLI::App& app, const GlobalOptions& global) override {
    global_ = &global;
    CLI::App* sub = app.add_subcommand("report", "write a self-contained HTML report of tests' results");
    sub->add_option("--series", selection_.series, "only tests of this series (repeatable)");
    sub->add_option("--variant", selection_.variants, "only tests of this variant (repeatable)");
    sub->add_option("--test", selection_.test_ids, "only this test (repeatable)");
    sub->add_option("--where", selection_.where,
                    "only tests whose results satisfy EXPR, as in `napkin query criteria --where` "
                    "(repeatable: all of them)")
        ->allow_extra_args(false);
    sub->add_option("--out", out_, "HTML file to write (- for standard output)")->required();
    return sub;
  }

  int Run() override {
    const std::string written = WrittenReportText(WriteCatalogueReport(global_->db_path, selection_, out_));
    // With --out - the report is standard output; what was written goes to stderr.
    fmt::print(out_ == util::kStandardOutputName ? stderr : stdout, "{}", written);
    return kExitOk;
  }

 private:
  const GlobalOptions* global_ = nullptr;
  ReportSelection selection_;
  std::string out_;
};

}  // namespace

std::unique_ptr<Command> MakeReportCommand() { return std::make_unique<ReportCommand>(); }

}  // namespace napkin::cli
