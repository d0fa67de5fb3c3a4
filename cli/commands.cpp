#include "cli/command.h"

namespace napkin::cli {

std::unique_ptr<Command> MakeTransformCommand();
std::unique_ptr<Command> MakeDemoCommand();
std::unique_ptr<Command> MakeInitCommand();
std::unique_ptr<Command> MakeImportCommand();
std::unique_ptr<Command> MakeQueryCommand();
std::unique_ptr<Command> MakeExportCommand();
std::unique_ptr<Command> MakeSynthCommand();
std::unique_ptr<Command> MakeRunCommand();
std::unique_ptr<Command> MakeStatusCommand();
std::unique_ptr<Command> MakeMergeCommand();
std::unique_ptr<Command> MakeCompareCommand();
std::unique_ptr<Command> MakeReportCommand();
std::unique_ptr<Command> MakeCorrelateCommand();
std::unique_ptr<Command> MakeServeCommand();

std::vector<std::unique_ptr<Command>> MakeCommands() {
  std::vector<std::unique_ptr<Command>> commands;
  commands.push_back(MakeInitCommand());
  commands.push_back(MakeImportCommand());
  commands.push_back(MakeQueryCommand());
  commands.push_back(MakeCompareCommand());
  commands.push_back(MakeExportCommand());
  commands.push_back(MakeTransformCommand());
  commands.push_back(MakeDemoCommand());
  commands.push_back(MakeSynthCommand());
  commands.push_back(MakeRunCommand());
  commands.push_back(MakeStatusCommand());
  commands.push_back(MakeMergeCommand());
  commands.push_back(MakeReportCommand());
  commands.push_back(MakeCorrelateCommand());
  commands.push_back(MakeServeCommand());
  return commands;
}

}  // namespace napkin::cli
