#include "tests/support/run_command.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "tests/support/test_support.h"

namespace napkin::test_support {

std::string ReadText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

pid_t StartProgram(const std::string& program, const std::vector<std::string>& args,
                   const std::filesystem::path& out_path, const std::filesystem::path& err_path,
                   const std::filesystem::path& cwd) {
  // Built before fork(): the child only calls async-signal-safe functions.
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>(program.c_str()));
  for (const auto& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    if (!cwd.empty() && chdir(cwd.c_str()) != 0) _exit(127);
    const int in = open("/dev/null", O_RDONLY);
    const int out = open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (in < 0 || out < 0 || err < 0 || dup2(in, 0) < 0 || dup2(out, 1) < 0 || dup2(err, 2) < 0) _exit(127);
    execv(program.c_str(), argv.data());
    _exit(127);
  }
  return pid;
}

int WaitProgram(pid_t pid) {
  int status = 0;
  if (pid <= 0 || waitpid(pid, &status, 0) != pid) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

CommandResult RunProgram(const std::string& program, const std::vector<std::string>& args,
                         const std::filesystem::path& cwd) {
  TempDir capture;
  const std::filesystem::path out_path = capture / "out", err_path = capture / "err";
  CommandResult result;
  result.exit_code = WaitProgram(StartProgram(program, args, out_path, err_path, cwd));
  result.out = ReadText(out_path);
  result.err = ReadText(err_path);
  return result;
}

}  // namespace napkin::test_support
