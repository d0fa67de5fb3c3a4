#pragma once
// A one-line progress bar on stderr for long commands (`napkin import` of a
// folder of tests): drawn only when stderr is a terminal and --quiet is off,
// so logs and pipes get no control characters.
#include <cstddef>
#include <string>

namespace napkin::cli {

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

}  // namespace napkin::cli
