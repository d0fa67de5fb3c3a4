#include "app/request_options.h"

#include <algorithm>
#include <limits>

#include "common/error.h"
#include "common/joined.h"
#include "util/text.h"

namespace napkin::app {
namespace {

// A value as typed, escaped and cut like all quoted input (docs/formats.md "Names, limits and
// escaping"), in single quotes; appended, never a literal prepended to a temporary (GCC bug 105329).
std::string InSingleQuotes(std::string_view text) {
  std::string quoted = "'";
  quoted += util::Abbreviated(text);
  quoted += '\'';
  return quoted;
}

// The service's and Python's spelling of an option: '_' for '-'.
std::string Underscored(std::string_view option) {
  std::string name(option);
  std::replace(name.begin(), name.end(), '-', '_');
  return name;
}

}  // namespace

std::string OptionName(FrontEnd front_end, std::string_view option) {
  switch (front_end) {
    case FrontEnd::kCommandLine:
      return "--" + std::string(option);
    case FrontEnd::kService:
      return "parameter '" + Underscored(option) + "'";
    case FrontEnd::kPython:
      return "argument '" + Underscored(option) + "'";
  }
  return std::string(option);
}

std::string OptionSetting(FrontEnd front_end, std::string_view option, std::string_view value) {
  switch (front_end) {
    case FrontEnd::kCommandLine:
      return "--" + std::string(option) + " " + std::string(value);
    case FrontEnd::kService:
      return Underscored(option) + "=" + std::string(value);
    case FrontEnd::kPython:
      return Underscored(option) + "=" + InSingleQuotes(value);
  }
  return std::string(option);
}

std::string ChoiceList(const std::vector<std::string>& choices) { return JoinedChoices(choices); }

std::string NotOneOfProblem(const std::string& spelled, const std::vector<std::string>& choices,
                            std::string_view text) {
  return spelled + " must be " + ChoiceList(choices) + "; it is " + InSingleQuotes(text);
}

std::optional<std::string> WholeNumberProblem(const std::string& spelled, std::string_view text,
                                              long long minimum, long long maximum) {
  const bool int_maximum = maximum == std::numeric_limits<int>::max();
  const std::string bounds = int_maximum
                                 ? "at least " + std::to_string(minimum)
                                 : "from " + std::to_string(minimum) + " to " + std::to_string(maximum);
  const std::optional<long long> number = util::ParseInteger(text);
  if (!number) return spelled + " must be a whole number " + bounds + "; it is " + InSingleQuotes(text);
  if (*number < minimum || (!int_maximum && *number > maximum))
    return spelled + " must be " + bounds + "; it is " + util::Abbreviated(text);
  if (*number > maximum)
    return spelled + " must be at most " + std::to_string(maximum) + "; it is " + util::Abbreviated(text);
  return std::nullopt;
}

RequestOptions& RequestOptions::Add(std::string option, std::string value) {
  values_.emplace_back(std::move(option), std::move(value));
  return *this;
}

std::string RequestOptions::Spelled(std::string_view option) const {
  return front_end_ == FrontEnd::kCommandLine ? std::string(option) : Underscored(option);
}

void RequestOptions::CheckKnown(std::initializer_list<std::string_view> known) const {
  std::vector<std::string> spelled;
  for (const std::string_view option : known) spelled.push_back(Spelled(option));
  for (const auto& [option, value] : values_) {
    if (std::find(spelled.begin(), spelled.end(), option) != spelled.end()) continue;
    std::string list;
    for (const std::string& name : spelled) list += (list.empty() ? "" : ", ") + name;
    // Named as given (the service's "dummy-type" is not its "dummy_type").
    const std::string given = front_end_ == FrontEnd::kCommandLine ? "--" + option
                              : front_end_ == FrontEnd::kService   ? "parameter '" + option + "'"
                                                                   : "argument '" + option + "'";
    throw UsageError("unknown " + given + " (" + (front_end_ == FrontEnd::kService ? "this route" : "it") +
                     " takes " + list + ").");
  }
}

std::vector<std::string> RequestOptions::All(std::string_view option) const {
  const std::string spelled = Spelled(option);
  std::vector<std::string> values;
  for (const auto& [name, value] : values_)
    if (name == spelled) values.push_back(value);
  return values;
}

std::vector<std::string> RequestOptions::CommaList(std::string_view option) const {
  std::vector<std::string> items;
  for (const std::string& value : All(option)) {
    std::size_t start = 0;
    for (;;) {
      const std::size_t comma = value.find(',', start);
      std::string item = value.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
      if (!item.empty()) items.push_back(std::move(item));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  }
  return items;
}

std::optional<std::string> RequestOptions::One(std::string_view option) const {
  std::vector<std::string> values = All(option);
  if (values.size() > 1) throw UsageError(Name(option) + " is given more than once.");
  if (values.empty()) return std::nullopt;
  return std::move(values.front());
}

std::string RequestOptions::Required(std::string_view option, std::string_view why) const {
  std::optional<std::string> value = One(option);
  if (!value) throw UsageError(Name(option) + " is required (" + std::string(why) + ").");
  return std::move(*value);
}

std::string RequestOptions::OneOf(std::string_view option, const std::vector<std::string>& choices,
                                  std::string_view fallback) const {
  const std::optional<std::string> value = One(option);
  if (!value) return std::string(fallback);
  if (std::find(choices.begin(), choices.end(), *value) == choices.end())
    throw UsageError(NotOneOfProblem(Name(option), choices, *value) + ".");
  return *value;
}

int RequestOptions::WholeNumber(std::string_view option, int minimum, int fallback) const {
  const std::optional<std::string> value = One(option);
  if (!value) return fallback;
  if (const std::optional<std::string> problem =
          WholeNumberProblem(Name(option), *value, minimum, std::numeric_limits<int>::max()))
    throw UsageError(*problem + ".");
  return static_cast<int>(*util::ParseInteger(*value));
}

}  // namespace napkin::app
