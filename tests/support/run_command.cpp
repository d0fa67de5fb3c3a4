#include "tests/support/run_command.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>
#include <utility>

#include "tests/support/test_support.h"

extern char** environ;

namespace napkin::test_support {

namespace {

// The command a run starts: its first argument that is no option ("run", "export", ...), the value
// of napkin's --db skipped.
std::string CommandOf(const std::vector<std::string>& args) {
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--db") {
      ++i;
      continue;
    }
    if (args[i].empty() || args[i][0] != '-') return args[i];
  }
  return {};
}

// Whether the sanitized program's leak check runs at the end of this start: the first start of
// each (program, command) in this test process, or every start with NAPKIN_TEST_LEAK_CHECK=all.
// The leak check scans the program's memory at exit, about 50 ms of a sanitized napkin's 130 ms
// start; the CLI tests start napkin some 2,300 times, most of them a command the same suite
// has run (and leak-checked) already. The GoogleTest programs, which run the libraries in process,
// check for leaks at every exit.
bool LeakCheckThisStart(const std::string& program, const std::vector<std::string>& args) {
  const char* every = std::getenv("NAPKIN_TEST_LEAK_CHECK");
  if (every != nullptr && std::string(every) == "all") return true;
  static std::mutex mutex;
  static std::set<std::pair<std::string, std::string>> checked;
  const std::lock_guard lock(mutex);
  return checked.emplace(program, CommandOf(args)).second;
}

// The child's environment: this process's, with the leak check off when `leak_check` is false
// (detect_leaks=0 appended to ASAN_OPTIONS, so it wins over an earlier setting).
std::vector<std::string> ChildEnvironment(bool leak_check) {
  std::vector<std::string> environment;
  std::string asan_options = "ASAN_OPTIONS=";
  for (char** entry = environ; *entry != nullptr; ++entry) {
    const std::string text = *entry;
    if (text.rfind("ASAN_OPTIONS=", 0) == 0)
      asan_options = text;
    else
      environment.push_back(text);
  }
  if (!leak_check) asan_options += (asan_options.back() == '=' ? "" : ":") + std::string("detect_leaks=0");
  if (asan_options != "ASAN_OPTIONS=") environment.push_back(asan_options);
  return environment;
}

}  // namespace

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
  std::vector<std::string> environment = ChildEnvironment(LeakCheckThisStart(program, args));
  std::vector<char*> envp;
  for (auto& entry : environment) envp.push_back(entry.data());
  envp.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    if (!cwd.empty() && chdir(cwd.c_str()) != 0) _exit(127);
    const int in = open("/dev/null", O_RDONLY);
    const int out = open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (in < 0 || out < 0 || err < 0 || dup2(in, 0) < 0 || dup2(out, 1) < 0 || dup2(err, 2) < 0) _exit(127);
    execve(program.c_str(), argv.data(), envp.data());
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
