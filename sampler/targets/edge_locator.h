#pragma once
// Finds the cell of a sorted edge list containing t in O(1) on average: a
// table of uniform buckets over [edges.front(), edges.back()] gives a start
// cell, then a short forward walk. Every box corner of every epoch needs a
// cell lookup, so a binary search each would be a large share of an
// environment-map optimization (tools/experiments/implementation_notes.md).

#include <algorithm>
#include <cmath>
#include <vector>

namespace nuld {

class EdgeLocator {
 public:
  EdgeLocator() = default;
  // `edges` strictly or weakly increasing, at least two of them.
  explicit EdgeLocator(const std::vector<double> &edges) {
    const int cells = int(edges.size()) - 1;
    lo_ = edges.front();
    const double span = edges.back() - lo_;
    buckets_ = 2 * cells;
    scale_ = span > 0 ? buckets_ / span : 0.0;
    start_.resize(buckets_ + 1);
    int c = 0;
    for (int b = 0; b <= buckets_; ++b) {
      const double t = lo_ + b / scale_;
      while (c < cells - 1 && edges[c + 1] <= t) ++c;
      start_[b] = c;
    }
  }

  // The last cell c with edges[c] <= t (clamped to [0, cells - 1]); `e` must
  // be the edges the locator was built from (it keeps no pointer, so owners
  // stay copyable).
  int cell(const std::vector<double> &e, double t) const {
    const int cells = int(e.size()) - 1;
    if (!(t > lo_)) return 0;  // also NaN
    const double f = (t - lo_) * scale_;
    int c = start_[f >= buckets_ ? buckets_ : int(f)];
    while (c < cells - 1 && e[c + 1] <= t) ++c;
    return c;
  }

 private:
  double lo_ = 0, scale_ = 0;
  int buckets_ = 0;
  std::vector<int> start_;
};

}  // namespace nuld
