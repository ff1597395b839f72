// The shared oracles of the sampling-target tests: see target_oracles.h.

#include "tests/sampler/target_oracles.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "sampler/io/image_io.h"
#include "sampler/point.h"
#include "sampler/sequences/rng.h"
#include "sampler/targets/grid_target.h"
#include "sampler/targets/image_targets.h"
#include "sampler/targets/target.h"
#include "sampler/targets/target_spec.h"
#include "tests/common/chi_square.h"

namespace nuld::test {

// ------------------------------------------------------------------ statistics

MassChiSquare chiSquare(const Target &sampled, const Target &reference, int n, int bins,
                        std::uint64_t seed) {
  MassChiSquare r;
  std::vector<double> observed(std::size_t(bins) * bins, 0.0);
  Rng rng(seed);
  for (int k = 0; k < n; ++k) {
    const double ux = rng.uniform();
    const double uy = rng.uniform();
    const Point2 x = sampled.invert({ux, uy}).x;
    if (!isFinite(x) || x.x < 0 || x.x > 1 || x.y < 0 || x.y > 1) {
      ++r.outside;
      continue;
    }
    if (!(sampled.pdf(x) > 0)) ++r.zeroDensity;
    const int i = std::min(int(x.x * bins), bins - 1), j = std::min(int(x.y * bins), bins - 1);
    observed[std::size_t(j) * bins + i] += 1;
  }
  std::vector<std::pair<double, double>> cells;  // (expected, observed)
  for (int j = 0; j < bins; ++j)
    for (int i = 0; i < bins; ++i) {
      const Box2 cell{{double(i) / bins, double(j) / bins},
                      {double(i + 1) / bins, double(j + 1) / bins}};
      const double m = reference.mass(cell);
      r.totalMass += m;
      cells.push_back({m * n, observed[std::size_t(j) * bins + i]});
    }
  std::sort(cells.begin(), cells.end());
  double pooledExpected = 0, pooledObserved = 0;
  std::vector<std::pair<double, double>> kept;
  for (const auto &[e, o] : cells) {
    if (e <= 0 && o > 0) r.inEmptyCells += std::size_t(o);
    if (e < 5) {
      pooledExpected += e;
      pooledObserved += o;
    } else {
      kept.push_back({e, o});
    }
  }
  if (pooledExpected > 0) {
    if (pooledExpected < 5 && !kept.empty()) {
      kept.front().first += pooledExpected;  // the smallest cell left
      kept.front().second += pooledObserved;
    } else {
      kept.push_back({pooledExpected, pooledObserved});
    }
  }
  for (const auto &[e, o] : kept) r.statistic += (o - e) * (o - e) / e;
  r.dof = int(kept.size()) - 1;
  r.pValue = r.dof > 0 ? regularizedGammaQ(0.5 * r.dof, 0.5 * r.statistic) : 1.0;
  if (r.inEmptyCells > 0) r.pValue = 0;
  return r;
}

// --------------------------------------------------------------- the targets

std::vector<double> uniformEdges(int cells) {
  std::vector<double> e(cells + 1);
  for (int i = 0; i <= cells; ++i) e[i] = double(i) / cells;
  return e;
}

Image envmapImage() {
  Image img;
  img.width = 8;
  img.height = 6;
  img.channels = 3;
  img.pixels.assign(std::size_t(img.width) * img.height * img.channels, 0.0f);
  for (int j = 0; j < img.height; ++j)
    for (int i = 0; i < img.width; ++i) {
      img.at(i, j, 0) = float(0.1 + ((3 * i + 5 * j) % 7) * 0.3);
      img.at(i, j, 1) = float(0.2 + ((i + 2 * j) % 5) * 0.25);
      img.at(i, j, 2) = float(0.05 + ((7 * i + j) % 4) * 0.5);
    }
  for (int i = 2; i <= 5; ++i)
    for (int ch = 0; ch < 3; ++ch) img.at(i, 4, ch) = 0.0f;
  for (int ch = 0; ch < 3; ++ch) img.at(0, 0, ch) = 20.0f;
  return img;
}

Image pictureImage() {
  const float values[3][5] = {{1, 2, 0, 4, 1}, {0, 0, 3, 1, 2}, {5, 1, 1, 0, 2}};
  Image img;
  img.width = 5;
  img.height = 3;
  img.channels = 1;
  img.pixels.resize(15);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 5; ++i) img.at(i, j, 0) = values[j][i];
  return img;
}

namespace {

Case closedFormCase(std::string name, const std::string &spec) {
  Case c;
  c.name = std::move(name);
  c.target = makeTarget(spec);
  return c;
}

int cellOf(const std::vector<double> &edges, double t) {
  return int(std::upper_bound(edges.begin(), edges.end(), t) - edges.begin());
}

Case gridCase(std::string name, std::shared_ptr<const Target> target, std::vector<double> xEdges,
              std::vector<double> yEdges) {
  Case c;
  c.name = std::move(name);
  c.target = std::move(target);
  c.xBreaks = xEdges;
  c.yBreaks = yEdges;
  c.region = [xEdges, yEdges](Point2 p) {
    return cellOf(xEdges, p.x) * 1000 + cellOf(yEdges, p.y);
  };
  c.firstAxis = 1;
  return c;
}

// Equal-area v of the lat-long rows' edges: v = (1 - cos theta) / 2.
std::vector<double> envmapRowEdges(int rows) {
  std::vector<double> e(rows + 1);
  for (int j = 0; j <= rows; ++j) e[j] = 0.5 * (1 - std::cos(kPi * j / rows));
  e.front() = 0;
  e.back() = 1;
  return e;
}

// Uneven edges, a zero row in the middle, zero cells.
const std::vector<double> kGridAx = {0, 0.1, 0.35, 0.4, 0.8, 1};
const std::vector<double> kGridAy = {0, 0.2, 0.25, 0.7, 1};
const std::vector<double> kGridAd = {1, 3, 0, 2, 0.5,  //
                                     0, 0, 0, 0, 0,    //
                                     4, 0, 7, 1, 2,    //
                                     0, 2, 2, 0, 9};
// Zero first and last rows, zero first column in some rows.
const std::vector<double> kGridBx = {0, 0.3, 0.5, 1};
const std::vector<double> kGridBy = {0, 0.15, 0.6, 0.65, 1};
const std::vector<double> kGridBd = {0, 0, 0,  //
                                     0, 5, 1,  //
                                     2, 0, 3,  //
                                     0, 0, 0};

}  // namespace

const std::vector<Case> &allCases() {
  static const std::vector<Case> cases = [] {
    std::vector<Case> v;
    v.push_back(closedFormCase("uniform", "uniform"));
    v.push_back(closedFormCase("bilinear", "bilinear:1,2,0.5,3"));
    v.push_back(closedFormCase("bilinear-zero-corner", "bilinear:0,1,1,2"));
    v.push_back(closedFormCase("gaussian", "gaussian:0.3,0.6,0.15"));
    v.push_back(closedFormCase("gaussian-mean-outside", "gaussian:-0.2,0.5,0.1"));
    Case disc = closedFormCase("quarterdisc", "quarterdisc");
    disc.yCurve = [](double x) { return std::sqrt(std::max(0.0, 1 - x * x)); };
    v.push_back(disc);
    Case step = closedFormCase("step", "step:0.4,1,3");
    step.xBreaks = {0.4};
    step.region = [](Point2 p) { return p.x < 0.4 ? 0 : 1; };
    v.push_back(step);
    Case halfStep = closedFormCase("step-default-weights", "step:0.5");
    halfStep.xBreaks = {0.5};
    halfStep.region = [](Point2 p) { return p.x < 0.5 ? 0 : 1; };
    v.push_back(halfStep);
    v.push_back(gridCase(
        "grid-a",
        std::make_shared<GridTarget>(kGridAx, kGridAy, kGridAd, "grid-a", Domain::Square, "grid-a"),
        kGridAx, kGridAy));
    v.push_back(gridCase(
        "grid-b",
        std::make_shared<GridTarget>(kGridBx, kGridBy, kGridBd, "grid-b", Domain::Square, "grid-b"),
        kGridBx, kGridBy));
    const Image env = envmapImage();
    v.push_back(gridCase("envmap", makeEnvmapTarget(env, "memory-envmap"), uniformEdges(env.width),
                         envmapRowEdges(env.height)));
    const Image pic = pictureImage();
    v.push_back(gridCase("image", makeImageTarget(pic, "memory-picture"), uniformEdges(pic.width),
                         uniformEdges(pic.height)));
    return v;
  }();
  return cases;
}

}  // namespace nuld::test
