#include "cli/command.h"

namespace napkin::cli {

std::unique_ptr<Command> MakeTransformCommand();
std::unique_ptr<Command> MakeDemoCommand();

std::vector<std::unique_ptr<Command>> MakeCommands() {
  std::vector<std::unique_ptr<Command>> commands;
  commands.push_back(MakeTransformCommand());
  commands.push_back(MakeDemoCommand());
  return commands;
}

}  // namespace napkin::cli
