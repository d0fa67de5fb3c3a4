#pragma once
// Running a program (the napkin binary) in CLI end-to-end tests: the one
// fork/exec helper every CLI test uses (tests/cli/cli_test_util.h wraps it
// for napkin).
#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace napkin::test_support {

struct CommandResult {
  int exit_code = -1;  // -1 when a signal ended the program
  std::string out;     // stdout
  std::string err;     // stderr
};

// The whole file as bytes (empty when it cannot be read).
std::string ReadText(const std::filesystem::path& path);

// Starts `program args...` (no shell: arguments are passed verbatim) in `cwd`
// (empty: the current directory) with stdin from /dev/null and stdout and
// stderr going to the given files; returns its process id. The address
// sanitizer's leak check runs at the program's exit the first time this test
// process starts each of its commands (the first argument that is no option),
// or every time with NAPKIN_TEST_LEAK_CHECK=all in the environment
// (run_command.cpp says why).
pid_t StartProgram(const std::string& program, const std::vector<std::string>& args,
                   const std::filesystem::path& out_path, const std::filesystem::path& err_path,
                   const std::filesystem::path& cwd = {});

// Waits for a started program: its exit status, -1 when a signal ended it.
int WaitProgram(pid_t pid);

// Runs `program args...` to completion (as StartProgram) and captures its output.
CommandResult RunProgram(const std::string& program, const std::vector<std::string>& args,
                         const std::filesystem::path& cwd = {});

}  // namespace napkin::test_support
