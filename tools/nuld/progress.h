#pragma once
// A progress bar on stderr: bar, count, rate-based ETA and a caller-supplied
// status (loss, alpha, ...). On a terminal it redraws one line at most ten
// times a second; otherwise (logs, CI) it prints a line every 10 %.

#include <chrono>
#include <string>

namespace nuld::cli {

class ProgressBar {
 public:
  ProgressBar(std::string label, long total, long start = 0, bool quiet = false);
  void update(long done, const std::string &status);
  void finish(const std::string &status);

 private:
  void draw(long done, const std::string &status, bool final);

  std::string label_;
  long total_, start_;
  bool quiet_, tty_;
  long lastDecile_;  // off a terminal: the tenth of the work last drawn
  std::chrono::steady_clock::time_point begin_, lastDraw_;
};

std::string formatDuration(double seconds);

}  // namespace nuld::cli
