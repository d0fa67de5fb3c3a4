#pragma once
// A napkin subcommand (osmium-tool style): Setup() declares the options and
// the checks of each option alone (CLI11 validators, cli/option_checks.h:
// exit status 2) without touching files; Run() first checks combinations
// of options (a UsageError: exit 2, cli/diagnostics.cpp), then does the work
// and returns the exit status (bad input: exit 1). One command_<name>.cpp per subcommand; the list is in
// commands.cpp.
#include <CLI/CLI.hpp>
#include <memory>
#include <string>
#include <vector>

namespace napkin::cli {

// Exit statuses of the CLI contract (README).
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;
inline constexpr int kExitPartial = 3;

struct GlobalOptions {
  std::string db_path = "napkin.db";  // --db
  bool quiet = false;                 // --quiet: no progress output
};

class Command {
 public:
  virtual ~Command() = default;
  // Adds the subcommand to `app`; `global` outlives the command.
  virtual CLI::App* Setup(CLI::App& app, const GlobalOptions& global) = 0;
  virtual int Run() = 0;
};

std::vector<std::unique_ptr<Command>> MakeCommands();

}  // namespace napkin::cli
