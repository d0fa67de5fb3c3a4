#pragma once
// A request's options as name -> values, whichever front end it came through
// (issue 43 points 5 and 7): the command line's options, the service's query
// parameters and the Python module's arguments are handed to one parser per
// workflow (ParseCompareRequest, app/comparison.h; ParseExportRequest,
// app/export.h) as text, so every front end takes the same options with the
// same defaults and refuses the same mistake with one sentence, which names
// the option as that front end spells it (issue 43 point 8): "--dummy-type"
// on the command line, "parameter 'dummy_type'" in the service, "argument
// 'dummy_type'" in Python.
//
// Options are named as the command line spells them without "--"
// ("dummy-type"); the service and Python write '_' for '-' ("dummy_type").
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace napkin::app {

enum class FrontEnd { kCommandLine, kService, kPython };

// `option` in a sentence: "--metrics", "parameter 'metrics'", "argument 'metrics'".
std::string OptionName(FrontEnd front_end, std::string_view option);

// `option` given `value`, as the front end writes it: "--by variant", "by=variant", "by='variant'".
std::string OptionSetting(FrontEnd front_end, std::string_view option, std::string_view value);

// The refusals shared with the command line's validators (cli/option_checks.h), without the final
// period CLI11's validators leave to the diagnostics: "<spelled> must be a, b or c; it is 'x'".
std::string NotOneOfProblem(const std::string& spelled, const std::vector<std::string>& choices,
                            std::string_view text);
// A whole number in [minimum, maximum] (maximum that of an int by default): nullopt when `text` is
// one, else "<spelled> must be at least 1; it is 0" or "... a whole number at least 1; it is 'x'".
std::optional<std::string> WholeNumberProblem(const std::string& spelled, std::string_view text,
                                              long long minimum, long long maximum);

// "a, b or c".
std::string ChoiceList(const std::vector<std::string>& choices);

class RequestOptions {
 public:
  explicit RequestOptions(FrontEnd front_end) : front_end_(front_end) {}

  // One value of `option`, named as the front end spells it ("dummy_type" in the service and
  // Python, "dummy-type" on the command line); repeated options add values, in order.
  RequestOptions& Add(std::string option, std::string value);

  FrontEnd front_end() const { return front_end_; }
  // OptionName and OptionSetting for this front end.
  std::string Name(std::string_view option) const { return OptionName(front_end_, option); }
  std::string Setting(std::string_view option, std::string_view value) const {
    return OptionSetting(front_end_, option, value);
  }

  // Throws UsageError for an option that is not one of `known` (the service: "unknown parameter
  // 'x' (this route takes series, by, ...)."): a misspelt one is refused, never ignored.
  void CheckKnown(std::initializer_list<std::string_view> known) const;

  // Every value of `option`, in order.
  std::vector<std::string> All(std::string_view option) const;
  // Every value of `option`, each split at ',' ("hic15,bric" as two), empty items left out.
  std::vector<std::string> CommaList(std::string_view option) const;
  // The value of an option given at most once (UsageError "<name> is given more than once."
  // otherwise); nullopt when absent.
  std::optional<std::string> One(std::string_view option) const;
  // One(option), else UsageError "<name> is required (<why>)."
  std::string Required(std::string_view option, std::string_view why) const;
  // One(option) or `fallback`, which must be one of `choices` (UsageError NotOneOfProblem).
  std::string OneOf(std::string_view option, const std::vector<std::string>& choices,
                    std::string_view fallback) const;
  // One(option) as a whole number of at least `minimum`, or `fallback` (UsageError
  // WholeNumberProblem).
  int WholeNumber(std::string_view option, int minimum, int fallback) const;

 private:
  // `option` as this front end spells it in Add.
  std::string Spelled(std::string_view option) const;

  FrontEnd front_end_;
  std::vector<std::pair<std::string, std::string>> values_;
};

}  // namespace napkin::app
