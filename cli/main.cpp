// napkin — six-degree-of-freedom head kinematics and injury criteria for
// catalogues of crash tests.
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>

#include "cli/command.h"
#include "engine/error.h"

int main(int argc, char** argv) {
  using namespace napkin::cli;
  CLI::App app{"napkin: head kinematics and injury criteria from crash-test head instrumentation"};
  app.require_subcommand(1);
  app.fallthrough();  // global options (--db, --quiet) may also follow the subcommand
  GlobalOptions global;
  app.add_option("--db", global.db_path, "catalogue file (SQLite)")->capture_default_str();
  app.add_flag("-q,--quiet", global.quiet, "no progress output");
  spdlog::set_pattern("%Y-%m-%dT%H:%M:%S.%e %^%l%$ %v");
  spdlog::set_default_logger(spdlog::stderr_color_mt("napkin"));

  auto commands = MakeCommands();
  std::vector<std::pair<CLI::App*, Command*>> parsed;
  for (auto& command : commands) parsed.emplace_back(command->Setup(app, global), command.get());

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return app.exit(error) == 0 ? kExitOk : kExitUsage;
  }
  try {
    for (auto& [sub, command] : parsed)
      if (sub->parsed()) return command->Run();
  } catch (const napkin::InputError& error) {
    std::cerr << "napkin: " << error.what() << "\n";
    return kExitFailure;
  } catch (const std::exception& error) {
    std::cerr << "napkin: " << error.what() << "\n";
    return kExitFailure;
  }
  return kExitUsage;
}
