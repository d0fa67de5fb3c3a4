#pragma once
// Progress on stderr for long commands: the bar of `napkin import` (a folder
// of tests) and the rate/ETA line of `napkin run`. Control characters are
// written only when stderr is a terminal and --quiet is off, so logs and
// pipes get none.
#include <cstddef>
#include <cstdint>
#include <string>

#include "jobs/scheduler.h"

namespace napkin::cli {

// Whether stderr is a terminal.
bool StderrIsTerminal();

// "m:ss" or "h:mm:ss"; "--:--" for a negative or non-finite duration.
std::string FormatDuration(double seconds);

class ProgressBar {
 public:
  // `enabled` false: every call does nothing.
  ProgressBar(std::size_t total, bool enabled);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  // Redraws "[#####.....]  45/200  label".
  void Update(std::size_t done, const std::string& label);
  // Erases the bar so a message can be printed on a clean line; the next
  // Update() draws it again.
  void Clear();
  bool enabled() const { return enabled_; }

  // Whether a bar would be shown: stderr is a terminal and not `quiet`.
  static bool WantedOnStderr(bool quiet);

 private:
  std::size_t total_;
  bool enabled_;
  bool drawn_ = false;
};

// `napkin run` progress: a rewritten line on a terminal, a log line every
// 10 s (and at the end) otherwise; nothing when `quiet`.
class RunProgressReporter {
 public:
  explicit RunProgressReporter(bool quiet);

  void operator()(const jobs::RunProgress& progress);
  // Ends the rewritten line, if one was drawn.
  void Finish();

 private:
  bool quiet_;
  bool terminal_;
  bool line_open_ = false;
  double last_log_s_ = 0.0;
};

}  // namespace napkin::cli
