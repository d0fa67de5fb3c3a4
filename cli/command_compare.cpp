// `napkin compare --series S --by variant|config`: each group's statistics of
// the chosen metrics and their differences from a baseline group with 95 %
// confidence intervals and p-values (app/comparison.h; docs/formats.md
// "napkin compare").
#include <fmt/core.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "app/comparison.h"
#include "app/request_options.h"
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
    // Each option's value goes to app::ParseCompareRequest as given, which checks it and supplies
    // the defaults, as for the service's and Python's compare (app/request_options.h).
    sub->add_option("--series", series_, "the series whose tests are compared")->required();
    sub->add_option("--by", by_,
                    "variant (Welch's t) or config (paired t over the same tests; default: variant)");
    sub->add_option("--baseline", baseline_,
                    "the group the others are compared with (default: first by name)");
    sub->add_option("--metrics", metrics_,
                    "comma-separated summary fields (default: " + DefaultMetricsText() + ")");
    sub->add_option("--config", configs_,
                    "stored config NAME or HASH-PREFIX: by variant, whose results (default: each test's "
                    "latest); by config, the configs compared (repeatable; default: all)");
    sub->add_option(
        "--scale", scale_,
        "log (default): HIC, BrIC, DAMAGE, accelerations and angular rates as ratios of geometric "
        "means; linear: every metric as a difference of means");
    sub->add_option("--equivalence", equivalence_,
                    "equivalence margin in % (two one-sided tests): a change within ±PCT is shown equivalent "
                    "(default: 10)");
    sub->add_option(
           "--limits", limits_,
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
    app::RequestOptions options(app::FrontEnd::kCommandLine);
    options.Add("series", series_);
    for (const auto& [name, value] : {std::pair{"by", &by_},
                                      {"baseline", &baseline_},
                                      {"scale", &scale_},
                                      {"equivalence", &equivalence_}})
      if (*value) options.Add(name, **value);
    for (const auto& [name, values] :
         {std::pair{"metrics", &metrics_}, {"config", &configs_}, {"limits", &limits_}})
      for (const std::string& value : *values) options.Add(name, value);
    const app::CompareRequest request = app::ParseCompareRequest(options);
    db::Catalogue catalogue = OpenCatalogue(*global_, /*read_only=*/true);
    const app::Comparison comparison = app::BuildComparison(catalogue, request);
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
  std::string series_;
  std::optional<std::string> by_;
  std::optional<std::string> baseline_;
  std::optional<std::string> scale_;
  std::optional<std::string> equivalence_;
  std::vector<std::string> metrics_;
  std::vector<std::string> configs_;
  std::vector<std::string> limits_;
  std::string format_ = "table";
};

}  // namespace

std::unique_ptr<Command> MakeCompareCommand() { return std::make_unique<CompareCommand>(); }

}  // namespace napkin::cli
