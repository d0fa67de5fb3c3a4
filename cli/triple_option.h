#pragma once
// Options that take three numbers, "X,Y,Z" (--orientation, --initial-velocity).
// Parsed from one argument rather than as a CLI11 vector option, which with
// CLI11 2.1 swallows the positional argument that follows it.
#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace napkin::cli {

// "0.5,-1e-3,2" -> {0.5, -0.001, 2}; nullopt unless exactly three finite numbers.
std::optional<std::vector<double>> ParseTriple(std::string_view text);

// Adds `name` to `command`; a malformed value is a usage error (exit 2) naming the option.
CLI::Option* AddTripleOption(CLI::App* command, const std::string& name, std::vector<double>& values,
                             const std::string& description);

}  // namespace napkin::cli
