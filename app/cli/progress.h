// A progress bar on stderr for long runs: shown only on a terminal, only once a run has taken
// more than a second, redrawn at most ten times a second, erased when done.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

namespace dw::app {

class ProgressBar {
 public:
  ProgressBar(std::string label, int64_t total, bool enabled);
  ~ProgressBar() { finish(); }
  void update(int64_t done);
  void finish();

 private:
  std::string label_;
  int64_t total_;
  bool enabled_;
  bool shown_ = false;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace dw::app
