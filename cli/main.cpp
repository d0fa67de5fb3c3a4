// napkin — six-degree-of-freedom head kinematics and injury criteria for
// catalogues of crash tests.
#include <CLI/CLI.hpp>
#include <exception>

#include "app/db_protection.h"
#include "cli/command.h"
#include "cli/diagnostics.h"
#include "cli/option_checks.h"
#include "common/version.h"

namespace {

int RunNapkin(int argc, char** argv) {
  using namespace napkin::cli;
  CLI::App app{"napkin: head kinematics and injury criteria from crash-test head instrumentation"};
  app.require_subcommand(1);
  app.fallthrough();  // global options (--db, --quiet) may also follow the subcommand
  GlobalOptions global;
  app.add_option("--db", global.db_path, "catalogue file (SQLite)")
      ->capture_default_str()
      ->check(PathCheck("--db"));
  app.add_flag("-q,--quiet", global.quiet,
               "no progress output and no information lines: warnings and errors only");
  // "napkin 0.1.0+g1a2b3c4" (docs/formats.md "Version string").
  app.set_version_flag("--version", "napkin " + napkin::Version());
  SetUpLogging();

  auto commands = MakeCommands();
  std::vector<std::pair<CLI::App*, Command*>> parsed;
  parsed.reserve(commands.size());
  for (auto& command : commands) parsed.emplace_back(command->Setup(app, global), command.get());

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    // --help and --version are "errors" of status 0: CLI11 prints them.
    if (error.get_exit_code() == 0) return app.exit(error) == 0 ? kExitOk : kExitUsage;
    return ReportOptionError(error);
  }
  if (global.quiet) SetQuietLogging();
  try {
    // No command writes its output over the catalogue (docs/formats.md "Output destinations").
    napkin::app::ProtectCatalogueFromOutput(global.db_path);
    for (auto& [sub, command] : parsed)
      if (sub->parsed()) return command->Run();
  } catch (...) {
    return ReportFailure(std::current_exception(), global.db_path);
  }
  return kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  // Setting up the command line (CLI11's options, the commands, the logger) may throw as well, e.g.
  // std::bad_alloc: that ends as every other failure does, with one sentence and its exit status
  // (cli/diagnostics.h), never in std::terminate. No catalogue is open before the command runs.
  try {
    return RunNapkin(argc, argv);
  } catch (...) {
    return napkin::cli::ReportFailure(std::current_exception(), "");
  }
}
