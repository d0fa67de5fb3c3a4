#include "cli/progress.h"

#include <fmt/core.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "util/text.h"

namespace napkin::cli {
namespace {
constexpr std::size_t kBarWidth = 30;
constexpr std::size_t kLabelWidth = 32;
}  // namespace

bool StderrIsTerminal() { return isatty(STDERR_FILENO) == 1; }

std::string FormatDuration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "--:--";
  const long total = std::lround(seconds);
  if (total >= 3600) return fmt::format("{}:{:02d}:{:02d}", total / 3600, (total / 60) % 60, total % 60);
  return fmt::format("{}:{:02d}", total / 60, total % 60);
}

std::string RateAndTimeLeft(std::int64_t done, std::int64_t total, double elapsed_s, const char* separator) {
  const double rate = elapsed_s > 0 ? static_cast<double>(done) / elapsed_s : 0.0;
  const double left = rate > 0 ? static_cast<double>(std::max<std::int64_t>(total - done, 0)) / rate : NAN;
  return fmt::format("{:.1f} tests/s{}ETA {}", rate, separator, FormatDuration(left));
}

ProgressLog::ProgressLog(std::string what, bool enabled, bool final_always)
    : what_(std::move(what)), enabled_(enabled), final_always_(final_always) {}

void ProgressLog::Update(std::int64_t done, std::int64_t failed, std::int64_t total, double elapsed_s) {
  if (!enabled_) return;
  const bool periodic = elapsed_s - last_log_s_ >= 10.0;
  const bool last = done >= total && (final_always_ || logged_);
  if (!periodic && !last) return;
  last_log_s_ = elapsed_s;
  logged_ = true;
  spdlog::info("{}: {}/{} tests{}, {}", what_, done, total,
               failed > 0 ? fmt::format(", {} failed", failed) : std::string(),
               RateAndTimeLeft(done, total, elapsed_s));
}

ProgressBar::ProgressBar(std::size_t total, bool enabled) : total_(total), enabled_(enabled && total > 0) {}

ProgressBar::~ProgressBar() { Clear(); }

bool ProgressBar::WantedOnStderr(bool quiet) { return !quiet && StderrIsTerminal(); }

void ProgressBar::Update(std::size_t done, const std::string& raw_label) {
  if (!enabled_) return;
  const std::string label = util::EscapeControl(raw_label);
  done = std::min(done, total_);
  const std::size_t filled = done * kBarWidth / total_;
  std::string line = "\r[";
  line.append(filled, '#');
  line.append(kBarWidth - filled, '.');
  line += "] " + std::to_string(done) + "/" + std::to_string(total_) + "  ";
  const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  line +=
      RateAndTimeLeft(static_cast<std::int64_t>(done), static_cast<std::int64_t>(total_), elapsed_s, "  ") +
      "  ";
  line += label.size() > kLabelWidth ? label.substr(0, kLabelWidth - 3) + "..." : label;
  line += "\x1b[K";  // erase the rest of the previous, longer line
  std::fputs(line.c_str(), stderr);
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressBar::Clear() {
  if (!enabled_ || !drawn_) return;
  std::fputs("\r\x1b[K", stderr);
  std::fflush(stderr);
  drawn_ = false;
}

RunProgressReporter::RunProgressReporter(bool quiet)
    : quiet_(quiet), terminal_(StderrIsTerminal()), log_("progress", !quiet && !terminal_) {}

void RunProgressReporter::operator()(const jobs::RunProgress& progress) {
  if (quiet_) return;
  const std::int64_t processed = progress.done + progress.failed;
  if (terminal_) {
    fmt::print(stderr, "\r{}/{} tests ({} failed)  {}   ", processed, progress.total, progress.failed,
               RateAndTimeLeft(processed, progress.total, progress.elapsed_s, "  "));
    std::fflush(stderr);
    line_open_ = true;
  } else {
    log_.Update(processed, progress.failed, progress.total, progress.elapsed_s);
  }
}

void RunProgressReporter::Finish() {
  if (line_open_) fmt::print(stderr, "\n");
  line_open_ = false;
}

}  // namespace napkin::cli
