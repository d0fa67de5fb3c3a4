#pragma once
// Checks of option values on the command line, each refusal one readable
// sentence naming the option (README: every error is one sentence). CLI11
// runs them on the text as typed, before converting it, and throws
// CLI::ValidationError("<option>: <sentence>"); cli/diagnostics.cpp
// (ReportOptionError) prints the sentence as "napkin: <sentence>." and exits
// with status 2. CLI11's own validators (Range, PositiveNumber, IsMember)
// are not used: their messages print the bounds of a double in full
// ("Value 0 not in range 0.000000 to 1797…", 309 digits) and lack the option.
#include <CLI/CLI.hpp>
#include <limits>
#include <string>
#include <vector>

namespace napkin::cli {

// A whole number in [minimum, maximum] (the maximum by default that of an
// int option): "--threads must be at least 1; it is 0".
CLI::Validator WholeNumberCheck(const std::string& option, long long minimum,
                                long long maximum = std::numeric_limits<int>::max());

// A finite number above 0: "--rate must be a number above 0; it is -5".
CLI::Validator PositiveNumberCheck(const std::string& option);

// One of `choices`: "--format must be table, csv or json; it is 'xml'".
CLI::Validator OneOfCheck(const std::string& option, const std::vector<std::string>& choices);

// A path that is not empty: an empty string names no file, and is never
// taken as "no option" (issue: `--results ''` once meant the catalogue):
// "--out must name a file; it is empty".
CLI::Validator PathCheck(const std::string& option);

// "a, b or c".
std::string ChoiceList(const std::vector<std::string>& choices);

}  // namespace napkin::cli
