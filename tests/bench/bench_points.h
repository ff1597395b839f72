#pragma once
// Uniform points the benchmarks cycle through (a fixed seed: every run
// times the same work).

#include <vector>

#include "sampler/point.h"
#include "sampler/sequences/rng.h"

namespace nuld::bench {

inline std::vector<Point2> uniformPoints(int n) {
  Rng rng(1);
  std::vector<Point2> u(n);
  for (Point2 &p : u) p = {rng.uniform(), rng.uniform()};
  return u;
}

}  // namespace nuld::bench
