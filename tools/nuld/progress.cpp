#include "tools/nuld/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace nuld::cli {

std::string formatDuration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "--:--";
  const long s = std::lround(seconds);
  char buf[32];
  if (s >= 3600)
    std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  else
    std::snprintf(buf, sizeof buf, "%ld:%02ld", s / 60, s % 60);
  return buf;
}

ProgressBar::ProgressBar(std::string label, long total, long start, bool quiet)
    : label_(std::move(label)),
      total_(std::max(total, 1L)),
      start_(start),
      quiet_(quiet),
      tty_(::isatty(STDERR_FILENO)),
      // Off a terminal a line is drawn only when a new tenth of the work is
      // done: at most ten lines a bar, the last one finish()'s.
      lastDecile_(std::clamp(start, 0L, total_) * 10 / total_),
      begin_(std::chrono::steady_clock::now()),
      lastDraw_(begin_) {}

void ProgressBar::update(long done, const std::string &status) {
  if (quiet_) return;
  const auto now = std::chrono::steady_clock::now();
  if (tty_) {
    if (now - lastDraw_ < std::chrono::milliseconds(100) && done < total_) return;
  } else {
    const long decile = done * 10 / total_;
    if (decile == lastDecile_ || done >= total_) return;  // finish() prints the last line
    lastDecile_ = decile;
  }
  lastDraw_ = now;
  draw(done, status, false);
}

void ProgressBar::finish(const std::string &status) {
  if (quiet_) return;
  draw(total_, status, true);
}

void ProgressBar::draw(long done, const std::string &status, bool final) {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - begin_).count();
  const long fresh = done - start_;
  const double eta = fresh > 0 ? elapsed / double(fresh) * double(total_ - done) : NAN;
  constexpr int kWidth = 24;
  const int filled = int(kWidth * std::clamp(double(done) / double(total_), 0.0, 1.0));
  std::string bar(filled, '#');
  bar.resize(kWidth, '-');
  std::fprintf(stderr, "%s%s [%s] %ld/%ld  %s  %s %s%s", tty_ ? "\r\033[K" : "", label_.c_str(),
               bar.c_str(), done, total_, status.c_str(), final ? "took" : "ETA",
               formatDuration(final ? elapsed : eta).c_str(), (final || !tty_) ? "\n" : "");
  std::fflush(stderr);
}

}  // namespace nuld::cli
