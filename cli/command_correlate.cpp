// `napkin correlate`: ISO/TS 18571 ratings of one derived channel
// (app/correlation.h; docs/formats.md "Correlation ratings"), in three
// forms: a test against a model's curve (--model), against another test
// (--reference-test), and each repeat of a variant against the variant's
// mean curve (--series --variant). Every rating is stored in the catalogue
// (`napkin query correlation`).
#include <fmt/core.h>

#include <optional>
#include <string>
#include <vector>

#include "app/correlation.h"
#include "app/table_output.h"
#include "cli/catalogue_option.h"
#include "cli/command.h"
#include "cli/option_checks.h"
#include "common/error.h"

namespace napkin::cli {
namespace {

class CorrelateCommand : public Command {
 public:
  CLI::App* Setup(CLI::App& app, const GlobalOptions& global) override {
    global_ = &global;
    CLI::App* sub = app.add_subcommand(
        "correlate", "ISO/TS 18571 rating of a test's channel against a model, another test, or its variant");
    sub->add_option("--test", test_, "the test rated (the reference curve)");
    sub->add_option("--model", model_,
                    "FILE[:COLUMN]: a model CSV, LS-DYNA *DEFINE_CURVE keyword file or nodout")
        ->check(PathCheck("--model"));
    sub->add_option("--model-units", model_units_,
                    "LS-DYNA files: the model's units LENGTH,TIME,MASS, e.g. mm,ms,kg or m,s,kg");
    sub->add_option("--reference-test", reference_test_,
                    "the reference test: --test's channel is rated against its same channel");
    sub->add_option("--series", series_, "with --variant: rate each repeat against the variant's mean curve");
    sub->add_option("--variant", variant_, "the variant whose repeats are rated");
    sub->add_option("--channel", channel_,
                    "derived channel, e.g. acc_resultant_g, acc_body_x_g, omega_body_x_radps, "
                    "omega_resultant_radps, alpha_body_x_radps2")
        ->required();
    sub->add_option("--start", start_,
                    "start of the evaluation interval in s (default: the curves' common start)");
    sub->add_option("--end", end_, "end of the evaluation interval in s (default: the curves' common end)");
    sub->add_option("--edition", edition_, "ISO/TS 18571 edition: 2014 or 2024")
        ->check(OneOfCheck("--edition", {"2014", "2024"}))
        ->capture_default_str();
    sub->add_option("--format", format_, "table, csv or json")
        ->check(OneOfCheck("--format", {"table", "csv", "json"}))
        ->capture_default_str();
    return sub;
  }

  int Run() override {
    const bool by_variant = series_ || variant_;
    const int forms = (model_ ? 1 : 0) + (reference_test_ ? 1 : 0) + (by_variant ? 1 : 0);
    if (forms != 1)
      throw UsageError(
          "give one of --model FILE, --reference-test ID (each with --test) or --series S "
          "--variant V.");
    if (by_variant && (!series_ || !variant_ || test_))
      throw UsageError("--series and --variant go together, without --test.");
    if (!by_variant && !test_) throw UsageError("--test is required with --model and --reference-test.");
    const app::RatingOptions options = app::ParseRatingOptions(channel_, start_, end_, edition_);
    const app::TableFormat format = app::ParseTableFormat(format_);
    db::Catalogue catalogue = OpenCatalogue(*global_);
    std::vector<app::RatingRow> rows;
    if (model_)
      rows.push_back(app::RateAgainstModel(catalogue, *test_, *model_, model_units_, options));
    else if (reference_test_)
      rows.push_back(app::RateAgainstTest(catalogue, *test_, *reference_test_, options));
    else
      rows = app::RateVariantRepeats(catalogue, *series_, *variant_, options);
    fmt::print("{}", app::FormatTable(app::RatingTable(rows), format));
    return kExitOk;
  }

 private:
  const GlobalOptions* global_ = nullptr;
  std::optional<std::string> test_, model_, model_units_, reference_test_, series_, variant_;
  std::string channel_;
  std::string start_, end_;
  std::string edition_ = "2024";
  std::string format_ = "table";
};

}  // namespace

std::unique_ptr<Command> MakeCorrelateCommand() { return std::make_unique<CorrelateCommand>(); }

}  // namespace napkin::cli
