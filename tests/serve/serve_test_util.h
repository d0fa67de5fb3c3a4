#pragma once
// The real `napkin serve` in end-to-end tests: started as the built binary on
// a free loopback port (port 0; its log line names the port), talked to with
// cpp-httplib's client or byte by byte over a raw loopback socket (RawConnection),
// stopped by its process id, every wait bounded.
#include <gtest/gtest.h>
#include <httplib.h>
// httplib.h includes glibc's <resolv.h>, whose macro _res (the resolver's state) is a
// parameter name in Eigen's headers, which the tests include after this one (unity build).
#ifdef _res
#undef _res
#endif
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <regex>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "tests/support/run_command.h"
#include "tests/support/test_support.h"

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

// A test with a fresh catalogue (napkin init) in a folder of its own.
class ServeCatalogueTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const CommandResult init = RunProgram(NAPKIN_BINARY, {"--db", db().string(), "init"}, dir_.path());
    ASSERT_EQ(init.exit_code, 0) << init.err;
  }
  fs::path db() const { return dir_ / "lab.db"; }

  TempDir dir_;
};

// One catalogue and one `napkin serve` on it for a whole suite (`Suite` the fixture deriving from
// this, so that each suite has its own): the suite's SetUpTestSuite fills the catalogue with
// Napkin(...) and calls Serve(). Its helpers compare the service with the command line.
template <typename Suite>
class ServedCatalogueSuite : public ::testing::Test {
 protected:
  static void TearDownTestSuite() {
    delete serve_;
    serve_ = nullptr;
    delete dir_;
    dir_ = nullptr;
  }
  void SetUp() override { ASSERT_TRUE(serve_ && serve_->port() > 0); }

  static fs::path dir() {
    if (!dir_) dir_ = new TempDir();
    return dir_->path();
  }
  static fs::path db() { return dir() / "lab.db"; }
  // `napkin --db DB ARGS...` in the suite's folder.
  static CommandResult Napkin(std::vector<std::string> args) {
    args.insert(args.begin(), {"--db", db().string()});
    return RunProgram(NAPKIN_BINARY, args, dir());
  }
  // Starts the suite's service (`napkin serve ARGS...` on a free loopback port).
  static void Serve(const std::vector<std::string>& args) {
    std::vector<std::string> all = {"--listen", "127.0.0.1:0"};
    all.insert(all.end(), args.begin(), args.end());
    serve_ = new ServeProcess(dir(), db(), all);
    ASSERT_GT(serve_->port(), 0) << serve_->log();
  }
  static httplib::Result Get(const std::string& target, const httplib::Headers& headers = {}) {
    return serve_->Client()->Get(target.c_str(), headers);
  }
  // The sentence of a JSON error body {"error": SENTENCE}.
  static std::string ErrorOf(const httplib::Result& result) {
    return nlohmann::json::parse(result->body).at("error").get<std::string>();
  }
  // The sentence of napkin's one-line error on stderr ("napkin: SENTENCE\n").
  static std::string CliSentence(const CommandResult& run) {
    std::string line = run.err;
    if (line.rfind("napkin: ", 0) == 0) line.erase(0, 8);
    while (!line.empty() && line.back() == '\n') line.pop_back();
    return line;
  }

  static inline TempDir* dir_ = nullptr;
  static inline ServeProcess* serve_ = nullptr;
};

// One answer as it came over a RawConnection.
struct RawAnswer {
  int status = 0;
  std::string header;  // the status line and the fields, up to the blank line
  std::string body;

  // The value of header field `name` (any case), empty when absent.
  std::string Field(std::string_view name) const {
    std::size_t at = header.find("\r\n");
    while (at != std::string::npos && at + 2 < header.size()) {
      const std::size_t end = header.find("\r\n", at + 2);
      const std::string line =
          header.substr(at + 2, end == std::string::npos ? std::string::npos : end - at - 2);
      const std::size_t colon = line.find(':');
      bool same = colon == name.size();
      for (std::size_t i = 0; same && i < name.size(); ++i)
        same = std::tolower(static_cast<unsigned char>(line[i])) ==
               std::tolower(static_cast<unsigned char>(name[i]));
      if (same) return line.substr(line.find_first_not_of(' ', colon + 1));
      at = end;
    }
    return {};
  }
};

// A loopback TCP connection to `napkin serve` that sends and reads bytes as a test chooses (slowly,
// pipelined, not at all), every wait bounded; closed when it goes.
class RawConnection {
 public:
  enum class Read { kData, kClosed, kTimeout };

  explicit RawConnection(int port) : fd_(socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0)) {
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<std::uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = fd_ >= 0 && connect(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0;
  }
  RawConnection(const RawConnection&) = delete;
  RawConnection& operator=(const RawConnection&) = delete;
  ~RawConnection() {
    if (fd_ >= 0) close(fd_);
  }

  bool connected() const { return connected_; }

  // All of `bytes`; false when the service has closed the connection (MSG_NOSIGNAL: no SIGPIPE).
  bool Send(std::string_view bytes) {
    while (!bytes.empty()) {
      const ssize_t sent = send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL);
      if (sent <= 0) return false;
      bytes.remove_prefix(static_cast<std::size_t>(sent));
    }
    return true;
  }

  // What of `bytes` fits without waiting: the count sent.
  std::size_t SendWhatFits(std::string_view bytes) {
    const ssize_t sent = send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    return sent > 0 ? static_cast<std::size_t>(sent) : 0;
  }

  // Waits at most `timeout` for bytes and keeps them (received()); kClosed once the service closed
  // the connection (end of stream or reset).
  Read ReadSome(std::chrono::milliseconds timeout) {
    pollfd ready{fd_, POLLIN, 0};
    if (poll(&ready, 1, static_cast<int>(timeout.count())) <= 0) return Read::kTimeout;
    char buffer[65536];
    const ssize_t n = recv(fd_, buffer, sizeof buffer, 0);
    if (n <= 0) return Read::kClosed;
    received_.append(buffer, static_cast<std::size_t>(n));
    return Read::kData;
  }

  // Everything received until the service closed the connection or `timeout` passed.
  std::string ReadUntilClosed(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline &&
           ReadSome(std::chrono::duration_cast<std::chrono::milliseconds>(
               deadline - std::chrono::steady_clock::now())) == Read::kData) {
    }
    return received_;
  }

  // The next answer (its body by Content-Length; none for a HEAD request), reading as needed for
  // at most `timeout`; nullopt when it did not arrive whole.
  std::optional<RawAnswer> ReadAnswer(bool head, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      if (std::optional<RawAnswer> answer = TakeAnswer(head)) return answer;
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0 || ReadSome(left) != Read::kData) return TakeAnswer(head);
    }
  }

  const std::string& received() const { return received_; }

 private:
  std::optional<RawAnswer> TakeAnswer(bool head) {
    const std::size_t end = received_.find("\r\n\r\n");
    if (end == std::string::npos) return std::nullopt;
    RawAnswer answer;
    answer.header = received_.substr(0, end);
    if (answer.header.rfind("HTTP/1.", 0) != 0 || answer.header.size() < 12) return std::nullopt;
    answer.status = std::stoi(answer.header.substr(9, 3));
    const std::string length = answer.Field("Content-Length");
    const std::size_t body_size = head || length.empty() ? 0 : std::stoul(length);
    if (received_.size() < end + 4 + body_size) return std::nullopt;
    answer.body = received_.substr(end + 4, body_size);
    received_.erase(0, end + 4 + body_size);
    return answer;
  }

  int fd_;
  bool connected_ = false;
  std::string received_;
};

// Sends `request` as it is on a new loopback connection to `port` and reads the answer until the
// service closes the connection (the request asks for it) or 10 s pass.
inline std::string RawExchange(int port, const std::string& request) {
  RawConnection connection(port);
  if (!connection.connected() || !connection.Send(request)) return {};
  return connection.ReadUntilClosed(std::chrono::seconds(10));
}

}  // namespace napkin::test_support
