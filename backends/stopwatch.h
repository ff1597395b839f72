#pragma once
// Wall-clock seconds for the studies' timing columns.

#include <chrono>

namespace nuld {

using Clock = std::chrono::steady_clock;

inline double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace nuld
