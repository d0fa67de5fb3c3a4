#pragma once
// Running the napkin executable from the end-to-end tests.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace napkin::testing {

struct CliResult {
  int exit_code = -1;  // -1 when killed by a signal
  std::string out;
  std::string err;
};

inline std::string ReadText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Starts `napkin args...` with stdout and stderr going to the given files.
inline pid_t StartNapkin(const std::vector<std::string>& args, const std::filesystem::path& out_path,
                         const std::filesystem::path& err_path) {
  const pid_t pid = fork();
  if (pid == 0) {
    const int out = open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (out < 0 || err < 0) _exit(127);
    dup2(out, STDOUT_FILENO);
    dup2(err, STDERR_FILENO);
    std::vector<char*> argv;
    std::string binary = NAPKIN_BINARY;
    argv.push_back(binary.data());
    std::vector<std::string> copies = args;
    for (std::string& arg : copies) argv.push_back(arg.data());
    argv.push_back(nullptr);
    execv(binary.c_str(), argv.data());
    _exit(127);
  }
  return pid;
}

// The exit status of a started napkin, -1 when a signal ended it.
inline int WaitNapkin(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Runs `napkin args...` to completion in `dir` (which holds its output files).
inline CliResult RunNapkin(const std::vector<std::string>& args, const std::filesystem::path& dir) {
  static int counter = 0;
  const std::string stem = "napkin-" + std::to_string(++counter);
  const auto out_path = dir / (stem + ".out"), err_path = dir / (stem + ".err");
  CliResult result;
  result.exit_code = WaitNapkin(StartNapkin(args, out_path, err_path));
  result.out = ReadText(out_path);
  result.err = ReadText(err_path);
  return result;
}

}  // namespace napkin::testing
