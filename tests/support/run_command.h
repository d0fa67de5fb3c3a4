#pragma once
// Running the napkin binary in CLI end-to-end tests.
#include <filesystem>
#include <string>
#include <vector>

namespace napkin::testing {

struct CommandResult {
  int exit_code = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};

// Runs `program args...` (no shell: arguments are passed verbatim) in `cwd`
// (empty: the current directory) and captures its output.
CommandResult RunProgram(const std::string& program, const std::vector<std::string>& args,
                         const std::filesystem::path& cwd = {});

}  // namespace napkin::testing
