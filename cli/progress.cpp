#include "cli/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace napkin::cli {
namespace {
constexpr std::size_t kBarWidth = 30;
constexpr std::size_t kLabelWidth = 32;
}  // namespace

ProgressBar::ProgressBar(std::size_t total, bool enabled) : total_(total), enabled_(enabled && total > 0) {}

ProgressBar::~ProgressBar() { Clear(); }

bool ProgressBar::WantedOnStderr(bool quiet) { return !quiet && isatty(STDERR_FILENO) == 1; }

void ProgressBar::Update(std::size_t done, const std::string& label) {
  if (!enabled_) return;
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

}  // namespace napkin::cli
