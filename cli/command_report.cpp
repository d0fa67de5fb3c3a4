// `napkin report`: one self-contained HTML file of the selected tests
// (app/report_builder.h; docs/formats.md "HTML report").
#include <fmt/core.h>

#include <string>

#include "app/report_builder.h"
#include "cli/command.h"
#include "cli/option_checks.h"
#include "util/output_destination.h"

namespace napkin::cli {
namespace {

class ReportCommand : public Command {
 public:
  CLI::App* Setup(CLI::App& app, const GlobalOptions& global) override {
    global_ = &global;
    CLI::App* sub = app.add_subcommand("report", "write a self-contained HTML report of tests' results");
    sub->add_option("--series", selection_.tests.series, "only tests of this series (repeatable)");
    sub->add_option("--variant", selection_.tests.variants, "only tests of this variant (repeatable)");
    sub->add_option("--test", selection_.tests.external_ids, "only this test (repeatable)");
    sub->add_option("--where", selection_.where,
                    "only tests whose results satisfy EXPR, as in `napkin query criteria --where` "
                    "(repeatable: all of them)")
        ->allow_extra_args(false);
    sub->add_option("--out", out_, "HTML file to write (- for standard output)")
        ->required()
        ->check(PathCheck("--out"));
    sub->add_option("--baseline", options_.baseline,
                    "the variant each compared series is compared with (default: first by name, as compare)");
    sub->add_option("--align", align_,
                    "t = 0 of the overlaid curves: recorded, or onset (first sample above --onset-threshold)")
        ->check(OneOfCheck("--align", {"recorded", "onset"}))
        ->capture_default_str();
    sub->add_option("--onset-threshold", options_.onset_threshold_g,
                    "resultant CG acceleration (g) that marks the impact onset for --align onset")
        ->check(PositiveNumberCheck("--onset-threshold"))
        ->capture_default_str();
    sub->add_option("--limits", options_.limits,
                    "limits the verdict checks per variant: a limits preset (config/limits, e.g. "
                    "fmvss201u) or a JSON file (repeatable)")
        ->check(PathCheck("--limits"))
        ->allow_extra_args(false);
    sub->add_option(
           "--model", options_.models,
           "a model file rated with `napkin correlate`: its stored ratings drawn with the ISO/TS 18571 "
           "corridors (repeatable)")
        ->check(PathCheck("--model"))
        ->allow_extra_args(false);
    sub->add_option("--model-units", options_.model_units,
                    "LS-DYNA model files: the model's units LENGTH,TIME,MASS, e.g. mm,ms,kg");
    return sub;
  }

  int Run() override {
    options_.align = app::ParseOverlayAlignment(align_);
    const std::string written =
        app::WrittenReportText(app::WriteCatalogueReport(global_->db_path, selection_, out_, options_));
    // With --out - the report is standard output; what was written goes to stderr.
    fmt::print(out_ == util::kStandardOutputName ? stderr : stdout, "{}", written);
    return kExitOk;
  }

 private:
  const GlobalOptions* global_ = nullptr;
  app::ReportSelection selection_;
  std::string out_;
  app::ReportOptions options_;
  std::string align_ = "recorded";
};

}  // namespace

std::unique_ptr<Command> MakeReportCommand() { return std::make_unique<ReportCommand>(); }

}  // namespace napkin::cli
