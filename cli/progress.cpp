#include "cli/progress.h"

#include <fmt/core.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

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

RunProgressReporter::RunProgressReporter(bool quiet) : quiet_(quiet), terminal_(StderrIsTerminal()) {}

void RunProgressReporter::operator()(const jobs::RunProgress& progress) {
  if (quiet_) return;
  const std::int64_t processed = progress.done + progress.failed;
  const double rate = progress.elapsed_s > 0 ? processed / progress.elapsed_s : 0.0;
  const double eta =
      rate > 0 ? static_cast<double>(std::max<std::int64_t>(progress.total - processed, 0)) / rate : NAN;
  if (terminal_) {
    fmt::print(stderr, "\r{}/{} tests ({} failed)  {:.1f} tests/s  ETA {}   ", processed, progress.total,
               progress.failed, rate, FormatDuration(eta));
    std::fflush(stderr);
    line_open_ = true;
  } else if (progress.elapsed_s - last_log_s_ >= 10.0 || processed >= progress.total) {
    last_log_s_ = progress.elapsed_s;
    spdlog::info("progress: {}/{} tests, {} failed, {:.2f} tests/s, ETA {}", processed, progress.total,
                 progress.failed, rate, FormatDuration(eta));
  }
}

void RunProgressReporter::Finish() {
  if (line_open_) fmt::print(stderr, "\n");
  line_open_ = false;
}

}  // namespace napkin::cli
