#pragma once
// The real `napkin serve` in end-to-end tests: started as the built binary on
// a free loopback port (port 0; its log line names the port), talked to with
// cpp-httplib's client, stopped by its process id, every wait bounded.
#include <gtest/gtest.h>
#include <httplib.h>
// httplib.h includes glibc's <resolv.h>, whose macro _res (the resolver's state) is a
// parameter name in Eigen's headers, which the tests include after this one (unity build).
#ifdef _res
#undef _res
#endif
#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/run_command.h"

namespace napkin::test_support {

namespace fs = std::filesystem;

// A `napkin serve` process; killed (SIGKILL, by its id) if a test ends without stopping it.
class ServeProcess {
 public:
  // Starts `napkin --db DB serve ARGS...` in `dir` and waits (at most 60 s) for its
  // "listening on" line. port() is 0 when it did not get there (it exited: see exit_code()).
  ServeProcess(const fs::path& dir, const fs::path& db, const std::vector<std::string>& args)
      : out_(dir / ("serve-" + std::to_string(++count_) + ".out")),
        err_(dir / ("serve-" + std::to_string(count_) + ".err")) {
    std::vector<std::string> all = {"--db", db.string(), "serve"};
    all.insert(all.end(), args.begin(), args.end());
    pid_ = StartProgram(NAPKIN_BINARY, all, out_, err_, dir);
    const std::regex listening(R"(listening on http://[^ ]+:([0-9]+) )");
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (std::chrono::steady_clock::now() < deadline) {
      std::smatch match;
      const std::string log = ReadText(err_);
      if (std::regex_search(log, match, listening)) {
        port_ = std::stoi(match[1].str());
        return;
      }
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        pid_ = -1;
        return;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  ServeProcess(const ServeProcess&) = delete;
  ServeProcess& operator=(const ServeProcess&) = delete;
  ~ServeProcess() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      WaitProgram(pid_);
    }
  }

  int port() const { return port_; }
  pid_t pid() const { return pid_; }
  std::string log() const { return ReadText(err_); }
  std::optional<int> exit_code() const { return exit_code_; }

  // A client with bounded timeouts.
  std::unique_ptr<httplib::Client> Client() const {
    auto client = std::make_unique<httplib::Client>("127.0.0.1", port_);
    client->set_connection_timeout(5, 0);
    client->set_read_timeout(30, 0);
    client->set_write_timeout(5, 0);
    return client;
  }

  // Sends `signal` and waits (at most 30 s) for the exit: its status, -1 for a signal, nullopt on timeout.
  std::optional<int> Stop(int signal = SIGTERM) {
    if (pid_ <= 0) return exit_code_;
    kill(pid_, signal);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (std::chrono::steady_clock::now() < deadline) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        return exit_code_;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return std::nullopt;
  }

 private:
  static inline int count_ = 0;
  fs::path out_;
  fs::path err_;
  pid_t pid_ = -1;
  int port_ = 0;
  std::optional<int> exit_code_;
};

}  // namespace napkin::test_support
