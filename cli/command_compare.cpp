// `napkin compare --series S --by variant|config`: each group's statistics of
// the chosen metrics and their differences from a baseline group with 95 %
// confidence intervals and p-values (app/comparison.h; docs/formats.md
// "napkin compare").
#include <fmt/core.h>

#include "app/comparison.h"
#include "cli/catalogue_option.h"
#include "cli/command.h"
#include "cli/option_checks.h"

namespace napkin::cli {
namespace {

class CompareCommand : public Command {
 public:
  CLI::App* Setup(CLI::App& app, const GlobalOptions& global) override {
    global_ = &global;
    CLI::App* sub = app.add_subcommand(
        "compare", "compare the variants (or processing configs) of a series: means, differences, 95 % CIs");
    sub->add_option("--series", request_.series, "the series whose tests are compared")->required();
    sub->add_option("--by", by_, "variant (Welch's t) or config (paired t over the same tests)")
        ->check(OneOfCheck("--by", {"variant", "config"}))
        ->capture_default_str();
    sub->add_option("--baseline", baseline_,
                    "the group the others are compared with (default: first by name)");
    sub->add_option("--metrics", request_.metrics,
                    "comma-separated summary fields (default: " + DefaultMetricsText() + ")")
        ->delimiter(',');
    sub->add_option("--config", request_.configs,
                    "stored config NAME or HASH-PREFIX: by variant, whose results (default: each test's "
                    "latest); by config, the configs compared (repeatable; default: all)");
    sub->add_option("--scale", scale_,
                    "log: HIC, BrIC, DAMAGE, accelerations and angular rates as ratios of geometric means; "
                    "linear: every metric as a difference of means")
        ->check(OneOfCheck("--scale", {"log", "linear"}))
        ->capture_default_str();
    sub->add_option("--equivalence", equivalence_,
                    "equivalence margin in % (two one-sided tests): a change within ±PCT is shown equivalent")
        ->capture_default_str();
    sub->add_option(
           "--limits", request_.limits,
           "limits to check per variant: a limits preset (config/limits, e.g. fmvss201u) or a JSON file "
           "(repeatable: sets that limit different metrics)")
        ->check(PathCheck("--limits"))
        ->allow_extra_args(false);
    sub->add_option("--format", format_, "table, csv or json")
        ->check(OneOfCheck("--format", {"table", "csv", "json"}))
        ->capture_default_str();
    return sub;
  }

  int Run() override {
    request_.by = app::ParseCompareBy(by_);
    request_.baseline = baseline_;
    request_.scale = app::ParseCompareScale(scale_);
    request_.equivalence_pct = app::ParseEquivalencePct(equivalence_);
    app::CheckOneLimitPerMetric(request_.limits);
    db::Catalogue catalogue = OpenCatalogue(*global_, /*read_only=*/true);
    const app::Comparison comparison = app::BuildComparison(catalogue, request_);
    fmt::print("{}", app::FormatComparison(comparison, app::ParseTableFormat(format_)));
    return kExitOk;
  }

 private:
  static std::string DefaultMetricsText() {
    std::string text;
    for (const std::string& metric : app::DefaultComparisonMetrics())
      text += (text.empty() ? "" : ",") + metric;
    return text;
  }

  const GlobalOptions* global_ = nullptr;
  app::ComparisonRequest request_;
  std::string by_ = "variant";
  std::optional<std::string> baseline_;
  std::string format_ = "table";
  std::string scale_ = "log";
  std::string equivalence_ = "10";
};

}  // namespace

std::unique_ptr<Command> MakeCompareCommand() { return std::make_unique<CompareCommand>(); }

}  // namespace napkin::cli
