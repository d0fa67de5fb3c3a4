#include "cli/triple_option.h"

#include <cmath>

#include "util/text.h"

namespace napkin::cli {

std::optional<std::vector<double>> ParseTriple(std::string_view text) {
  std::vector<double> values;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    const std::optional<double> value = util::ParseDouble(
        text.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
    if (!value || !std::isfinite(*value)) return std::nullopt;
    values.push_back(*value);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  if (values.size() != 3) return std::nullopt;
  return values;
}

CLI::Option* AddTripleOption(CLI::App* command, const std::string& name, std::vector<double>& values,
                             const std::string& description) {
  return command
      ->add_option_function<std::string>(
          name,
          [&values, name](const std::string& text) {
            const std::optional<std::vector<double>> parsed = ParseTriple(text);
            if (!parsed)
              throw CLI::ValidationError(name, name + " needs three comma-separated numbers, e.g. " + name +
                                                   "=0.1,0,-0.2; it is '" + util::Abbreviated(text) + "'");
            values = *parsed;
          },
          description)
      ->type_name("X,Y,Z");
}

}  // namespace napkin::cli
