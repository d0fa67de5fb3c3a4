#include "cli/option_checks.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "app/request_options.h"
#include "util/text.h"

namespace napkin::cli {
namespace {

// The value as typed, quoted and cut like all quoted input (docs/formats.md
// "Names, limits and escaping").
std::string Quoted(const std::string& text) { return "'" + util::Abbreviated(text) + "'"; }

}  // namespace

std::string ChoiceList(const std::vector<std::string>& choices) { return app::ChoiceList(choices); }

CLI::Validator WholeNumberCheck(const std::string& option, long long minimum, long long maximum) {
  const bool int_maximum = maximum == std::numeric_limits<int>::max();
  const std::string bounds = int_maximum
                                 ? "at least " + std::to_string(minimum)
                                 : "from " + std::to_string(minimum) + " to " + std::to_string(maximum);
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        return app::WholeNumberProblem(option, text, minimum, maximum).value_or("");
      },
      "INT " + bounds);
}

CLI::Validator PositiveNumberCheck(const std::string& option) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        const std::optional<double> number = util::ParseDouble(text);
        if (!number || !std::isfinite(*number))
          return option + " must be a number above 0; it is " + Quoted(text);
        if (*number <= 0.0) return option + " must be above 0; it is " + util::Abbreviated(text);
        return {};
      },
      "NUMBER above 0");
}

CLI::Validator PathCheck(const std::string& option) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        if (text.empty()) return option + " must name a file or folder; it is empty";
        return {};
      },
      "PATH");
}

CLI::Validator OneOfCheck(const std::string& option, const std::vector<std::string>& choices) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        if (std::find(choices.begin(), choices.end(), text) != choices.end()) return {};
        return app::NotOneOfProblem(option, choices, text);
      },
      "one of " + ChoiceList(choices));
}

}  // namespace napkin::cli
