#include "cli/diagnostics.h"

#include <fmt/format.h>
#include <spdlog/pattern_formatter.h>
#include <spdlog/sinks/base_sink.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <cctype>
#include <cstdio>
#include <memory>
#include <mutex>
#include <new>

#include "app/failure.h"
#include "cli/command.h"
#include "util/text.h"

namespace napkin::cli {
namespace {

// stderr sink: user-facing levels carry the program name (the one-sentence
// error contract in the README), information lines a timestamp (long runs
// are logged to files).
// Set once a long-running command (serve) is under way: warnings and errors carry a timestamp.
std::atomic<bool> timestamp_every_line{false};

class StderrSink final : public spdlog::sinks::base_sink<std::mutex> {
 public:
  StderrSink() : info_formatter_("%Y-%m-%dT%H:%M:%S.%e %l %v") {}

 protected:
  void sink_it_(const spdlog::details::log_msg& message) override {
    // The one gate to stderr: control characters from file names, ids or
    // file contents are shown escaped, never sent to the terminal.
    const std::string escaped =
        util::EscapeControl(std::string_view(message.payload.data(), message.payload.size()));
    const std::string_view text(escaped);
    switch (message.level) {
      case spdlog::level::err:
      case spdlog::level::critical:
        std::fprintf(stderr, "%snapkin: %.*s\n", Timestamp(message).c_str(), static_cast<int>(text.size()),
                     text.data());
        break;
      case spdlog::level::warn:
        std::fprintf(stderr, "%snapkin: warning: %.*s\n", Timestamp(message).c_str(),
                     static_cast<int>(text.size()), text.data());
        break;
      default: {
        spdlog::details::log_msg escaped_message = message;
        escaped_message.payload = text;
        spdlog::memory_buf_t line;
        info_formatter_.format(escaped_message, line);
        std::fwrite(line.data(), 1, line.size(), stderr);
      }
    }
  }
  void flush_() override { std::fflush(stderr); }

 private:
  // The time of `message` and a space, as the information lines give it; empty unless
  // TimestampEveryLogLine was called.
  std::string Timestamp(const spdlog::details::log_msg& message) {
    if (!timestamp_every_line.load()) return {};
    spdlog::details::log_msg bare = message;
    bare.payload = {};
    spdlog::memory_buf_t line;
    time_formatter_.format(bare, line);
    return std::string(line.data(), line.size());
  }

  spdlog::pattern_formatter info_formatter_;
  // No end of line: the time goes before "napkin: ".
  spdlog::pattern_formatter time_formatter_{"%Y-%m-%dT%H:%M:%S.%e ", spdlog::pattern_time_type::local, ""};
};

}  // namespace

void TimestampEveryLogLine() { timestamp_every_line = true; }

void SetQuietLogging() { spdlog::default_logger()->set_level(spdlog::level::warn); }

int ReportOptionError(const CLI::ParseError& error) {
  std::string text = error.what();
  const std::string kind = error.get_name();
  const auto ends_with = [&](std::string_view tail) { return text.ends_with(tail); };
  if (kind == "ValidationError") {
    // "<option>: <sentence>": napkin's checks and callbacks name the option in their sentence.
    const std::size_t colon = text.find(": ");
    if (colon != std::string::npos) text.erase(0, colon + 2);
  } else if (kind == "ArgumentMismatch" && ends_with(" missing")) {
    // "--threads: 1 required INT missing"
    text = text.substr(0, text.find(':')) + " needs a value";
  } else if (kind == "ConversionError" && text.starts_with("Could not convert: ")) {
    // "Could not convert: --seed = -1"
    text.erase(0, std::string_view("Could not convert: ").size());
    const std::size_t equals = text.find(" = ");
    if (equals != std::string::npos)
      text = text.substr(0, equals) + " cannot be '" + util::Abbreviated(text.substr(equals + 3)) + "'";
  } else if (kind == "ExcludesError") {
    // "--duration excludes --samples"
    const std::size_t excludes = text.find(" excludes ");
    if (excludes != std::string::npos)
      text = text.substr(0, excludes) + " and " + text.substr(excludes + 10) + " cannot be given together";
  }
  // "The following argument ..." reads on after "napkin: " in lower case; "KIND is ..." stays.
  if (text.size() > 1 && std::isupper(static_cast<unsigned char>(text[0])) &&
      std::islower(static_cast<unsigned char>(text[1])))
    text.front() = static_cast<char>(std::tolower(static_cast<unsigned char>(text.front())));
  while (!text.empty() && (text.back() == '.' || std::isspace(static_cast<unsigned char>(text.back()))))
    text.pop_back();
  if (kind == "ValidationError")
    spdlog::error("{}.", text);
  else
    spdlog::error("{}; `napkin --help` lists the commands, `napkin COMMAND --help` their options.", text);
  return kExitUsage;
}

void SetUpLogging() {
  auto logger = std::make_shared<spdlog::logger>("napkin", std::make_shared<StderrSink>());
  logger->flush_on(spdlog::level::trace);  // diagnostics interleave with the progress bar: never buffer
  spdlog::set_default_logger(std::move(logger));
}

int ReportFailure(const std::exception_ptr& error, const std::string& db_path) {
  const app::Failure failure = app::DescribeFailure(error, db_path);
  spdlog::error("{}", failure.sentence);
  return failure.category == app::FailureCategory::kUsage ? kExitUsage : kExitFailure;
}

}  // namespace napkin::cli
