#pragma once
// One name <-> enum table per vocabulary (solver, bias mode, CFC variant,
// severity, sensor kind, LS-DYNA units): the table beside each enum is the
// only place its names are spelled. Beside the table, one line
//   constexpr const auto& NamesOf(SolverKind) { return kSolverNames; }
// says which table names the enum; NameOf(value) and ParseName<Enum>(name)
// find it by argument-dependent lookup, the JSON readers and writers and the
// CLI option checks call those, and kXs = ValuesOf(table) lists the values
// in table order (for messages that name what would be accepted).
#include <array>
#include <cstddef>
#include <optional>
#include <string_view>

namespace napkin::engine {

template <typename Enum>
struct NamedValue {
  Enum value;
  const char* name;
};

template <typename Enum, std::size_t N>
constexpr std::array<Enum, N> ValuesOf(const std::array<NamedValue<Enum>, N>& names) {
  std::array<Enum, N> values{};
  for (std::size_t i = 0; i < N; ++i) values[i] = names[i].value;
  return values;
}

// The name of `value`. Every table lists every value of its enum
// (tests/engine/vocabulary_test.cpp), so the fallback is never taken.
template <typename Enum, std::size_t N>
constexpr const char* NameIn(const std::array<NamedValue<Enum>, N>& names, Enum value) {
  for (const NamedValue<Enum>& entry : names)
    if (entry.value == value) return entry.name;
  return names[0].name;
}

// The value called `name` (exact spelling), or nullopt.
template <typename Enum, std::size_t N>
constexpr std::optional<Enum> ValueNamed(const std::array<NamedValue<Enum>, N>& names,
                                         std::string_view name) {
  for (const NamedValue<Enum>& entry : names)
    if (name == entry.name) return entry.value;
  return std::nullopt;
}

// The one spelling of `value`, from the table NamesOf(Enum) names.
template <typename Enum>
constexpr const char* NameOf(Enum value) {
  return NameIn(NamesOf(Enum{}), value);
}

// The value of Enum spelled `name` (exact spelling), or nullopt.
template <typename Enum>
constexpr std::optional<Enum> ParseName(std::string_view name) {
  return ValueNamed(NamesOf(Enum{}), name);
}

}  // namespace napkin::engine
