#pragma once
// The one way napkin lists names in a message or an SQL column list:
// "a, b, c" (choices: "a, b or c"). Header-only, so every folder (db included, which does not see
// formats/) shares it.
#include <functional>
#include <ranges>
#include <string>

namespace napkin {

// The text of each of `items` (`text` of the item, e.g. &QueryField::name;
// the item itself by default), ", " between them; "" when there are none.
// (A separator follows only text already written: leading empty items leave none.)
template <std::ranges::input_range Items, typename Text = std::identity>
std::string Joined(const Items& items, Text text = {}) {
  std::string list;
  for (const auto& item : items) {
    if (!list.empty()) list += ", ";
    list += std::invoke(text, item);
  }
  return list;
}

// The same list with " or " before its last item, for choices: "a, b or c".
template <std::ranges::input_range Items, typename Text = std::identity>
std::string JoinedChoices(const Items& items, Text text = {}) {
  std::string list;
  const auto count = std::ranges::distance(items);
  decltype(std::ranges::distance(items)) i = 0;
  for (const auto& item : items) {
    if (i > 0) list += i + 1 == count ? " or " : ", ";
    list += std::invoke(text, item);
    ++i;
  }
  return list;
}

}  // namespace napkin
