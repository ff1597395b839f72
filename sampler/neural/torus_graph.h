#pragma once
// The k-nearest-neighbour graph of a point set on the unit torus, which the
// graph generator (graph_net.h) passes messages over. A Cranley-Patterson
// rotation moves every point by the same offset modulo 1, so toroidal
// distances, and with them this graph and its edge offsets, are the same for
// every z: the graph is built once per base set.

#include <cstdint>
#include <span>
#include <vector>

#include "sampler/point.h"

namespace nuld {

struct TorusGraph {
  std::size_t n = 0, k = 0;
  // neighbours[i k + j]: the index of point i's (j+1)-th nearest other point
  // (ties broken by index); offsets[i k + j]: that neighbour minus point i,
  // wrapped into [-1/2, 1/2)^2.
  std::vector<std::int64_t> neighbours;
  std::vector<Point2> offsets;
};

// The difference b - a on the torus, each coordinate in [-1/2, 1/2).
Point2 torusDifference(Point2 a, Point2 b);

// Exact k nearest neighbours by toroidal distance, over a bucket grid (about
// one point per cell), so N = 2^20 stays near-linear. k is clamped to N - 1
// (N = 1: no edges). Points outside [0, 1)^2 are wrapped first.
TorusGraph buildTorusGraph(std::span<const Point2> points, std::size_t k);

}  // namespace nuld
