#pragma once
// Progress on stderr for long commands: the bar of `napkin import` (a folder
// of tests) and the rate/ETA line of `napkin run`. Control characters are
// written only when stderr is a terminal and --quiet is off, so logs and
// pipes get none.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>

#include "jobs/scheduler.h"

namespace napkin::cli {

// Whether stderr is a terminal.
bool StderrIsTerminal();

// "m:ss" or "h:mm:ss"; "--:--" for a negative or non-finite duration.
std::string FormatDuration(double seconds);

// The rate of `done` tests in `elapsed_s` and the time the rest of `total`
// take at that rate, joined by `separator`: "12.3 tests/s, ETA 1:05" ("ETA
// --:--" before the first test).
std::string RateAndTimeLeft(std::int64_t done, std::int64_t total, double elapsed_s,
                            const char* separator = ", ");

// Progress of a long command over a known number of tests where stderr is
// no terminal (a log, a pipe, a service's journal): an info line "<what>:
// 4500/20000 tests, 2 failed, 120.5 tests/s, ETA 2:08" ("2 failed" only when
// some did) every 10 s and once at the end; nothing when `enabled` is false.
class ProgressLog {
 public:
  // `final_always` false: the last line only after a line every 10 s (a
  // short import stays quiet: its result lines on stdout say everything).
  ProgressLog(std::string what, bool enabled, bool final_always = true);
  // `done` of `total` tests (`failed` of them failed) after `elapsed_s`.
  void Update(std::int64_t done, std::int64_t failed, std::int64_t total, double elapsed_s);

 private:
  std::string what_;
  bool enabled_;
  bool final_always_;
  bool logged_ = false;
  double last_log_s_ = 0.0;
};

class ProgressBar {
 public:
  // `enabled` false: every call does nothing.
  ProgressBar(std::size_t total, bool enabled);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  // Redraws "[#####.....]  45/200  12.3 tests/s  ETA 0:13  label" (the rate
  // since the bar was made).
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
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

// `napkin run` progress: a rewritten line on a terminal, a ProgressLog
// otherwise; nothing when `quiet`.
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
  ProgressLog log_;
};

}  // namespace napkin::cli
