#include "sampler/bluenoise/gaussian_blue_noise.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "sampler/bluenoise/target_sample.h"
#include "sampler/io/round_trip.h"
#include "sampler/sequences/rng.h"

namespace nuld {
namespace {

constexpr double kCutoff = 8;  // in units of the pair's width

// Points bucketed on a square grid over [0, 1)^2 for radius queries.
class BucketGrid {
 public:
  // About one point per cell at most: finer cells only cost memory.
  BucketGrid(std::span<const Point2> points, double cell)
      : cells_(std::clamp(int(1 / std::max(cell, 1e-9)), 1,
                          std::max(1, int(std::sqrt(double(points.size())))))),
        start_(std::size_t(cells_) * std::size_t(cells_) + 1) {
    std::vector<int> cellOf(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      cellOf[i] = index(points[i]);
      ++start_[std::size_t(cellOf[i]) + 1];
    }
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    items_.resize(points.size());
    std::vector<int> fill(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < points.size(); ++i)
      items_[std::size_t(fill[std::size_t(cellOf[i])]++)] = int(i);
  }
  // Calls f(j) for every point in the cells within `radius` of p (wrapping
  // around the torus when `wrap`).
  template <class F>
  void near(Point2 p, double radius, bool wrap, F &&f) const {
    const int reach = std::min(cells_, int(std::ceil(radius * cells_)));
    const int cx = coordinate(p.x), cy = coordinate(p.y);
    for (int dy = -reach; dy <= reach; ++dy) {
      int y = cy + dy;
      if (wrap) {
        if (2 * reach + 1 > cells_ && dy >= -reach + cells_) break;  // each row once
        y = (y % cells_ + cells_) % cells_;
      } else if (y < 0 || y >= cells_) {
        continue;
      }
      for (int dx = -reach; dx <= reach; ++dx) {
        int x = cx + dx;
        if (wrap) {
          if (2 * reach + 1 > cells_ && dx >= -reach + cells_) break;
          x = (x % cells_ + cells_) % cells_;
        } else if (x < 0 || x >= cells_) {
          continue;
        }
        const int c = y * cells_ + x;
        for (int k = start_[std::size_t(c)]; k < start_[std::size_t(c) + 1]; ++k)
          f(items_[std::size_t(k)]);
      }
    }
  }

 private:
  int coordinate(double v) const { return std::clamp(int(v * cells_), 0, cells_ - 1); }
  int index(Point2 p) const { return coordinate(p.y) * cells_ + coordinate(p.x); }

  int cells_;
  std::vector<int> start_, items_;
};

Point2 difference(Point2 a, Point2 b, bool wrap) {
  Point2 d = a - b;
  if (wrap) d = {d.x - std::round(d.x), d.y - std::round(d.y)};
  return d;
}

}  // namespace

// The adaptive target's fixed sample, bucketed once.
struct GaussianBlueNoise::SampleIndex {
  BucketGrid grid;
  double widest;
};

std::size_t GaussianBlueNoiseSettings::samplesFor(std::size_t n) const {
  return targetSamples > 0 ? targetSamples : std::max<std::size_t>(4 * n, 4096);
}

std::string GaussianBlueNoiseSettings::describe() const {
  std::ostringstream s;
  s << "iterations=" << iterations << " sigma=" << formatRoundTrip(sigma)
    << " step=" << formatRoundTrip(step) << " boundary=" << toString(boundary)
    << " target_samples=" << targetSamples << " seed=" << seed;
  return s.str();
}

void GaussianBlueNoiseSettings::validate() const {
  auto bad = [](const std::string &what) { throw std::invalid_argument("gbn: " + what); };
  if (iterations < 0 || iterations > 10000000) bad("iterations must be in [0, 10^7]");
  if (!(sigma >= 0.1 && sigma <= 10)) bad("sigma must be in [0.1, 10] (units of the spacing)");
  if (!(step > 0 && step <= 4)) bad("step must be in (0, 4]");
  if (targetSamples > (std::size_t(1) << 24)) bad("target samples must be at most 2^24");
}

GaussianBlueNoise::GaussianBlueNoise(const Target &target,
                                     const GaussianBlueNoiseSettings &settings, std::size_t n)
    : target_(target), settings_(settings), n_(n) {
  settings_.validate();
  if (n == 0) throw std::invalid_argument("gbn: a set needs at least one point");
  s_ = settings_.sigma / std::sqrt(2.0 * double(n));
  adaptive_ = !target.isUniform();
  if (adaptive_ && settings_.boundary == BlueNoiseBoundary::Toroidal)
    throw std::invalid_argument("gbn: the toroidal variant is for the uniform target only");
  if (!adaptive_) return;
  sample_ =
      stratifiedTargetSample(target, settings_.samplesFor(n), hash3(settings_.seed, 0x6B7, n));
  sampleWidth_.resize(sample_.size());
  for (std::size_t m = 0; m < sample_.size(); ++m) sampleWidth_[m] = widthAt(sample_[m]);
  const double widest = *std::max_element(sampleWidth_.begin(), sampleWidth_.end());
  sampleIndex_ = std::make_shared<const SampleIndex>(
      SampleIndex{BucketGrid(sample_, kCutoff * widest), widest});
}

double GaussianBlueNoise::widthAt(Point2 p) const {
  if (!adaptive_) return s_;
  // Where the target has no density (a point pushed off its support) the
  // width stays the uniform one: a wide kernel there would push a whole
  // neighbourhood of the support away.
  const double rho = target_.pdf(p);
  const double s = std::isfinite(rho) && rho > 0 ? s_ / std::sqrt(rho) : s_;
  return std::clamp(s, s_ / 8, 8 * s_);
}

void GaussianBlueNoise::forces(std::span<const Point2> points, std::span<Point2> out,
                               bool allPairs) const {
  std::vector<double> width(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) width[i] = widthAt(points[i]);
  forces(points, width, out, allPairs);
}

void GaussianBlueNoise::forces(std::span<const Point2> points, std::span<const double> width,
                               std::span<Point2> out, bool allPairs) const {
  const std::size_t n = points.size();
  const bool wrap = settings_.boundary == BlueNoiseBoundary::Toroidal;
  const double widest = n == 0 ? 0 : *std::max_element(width.begin(), width.end());
  const double sampleWidest = sampleIndex_ ? sampleIndex_->widest : 0;
  const BucketGrid grid(points, kCutoff * widest);
  const double sampleMass = sample_.empty() ? 0 : double(n) / double(sample_.size());
  tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
    const Point2 p = points[i];
    Point2 f{0, 0};
    auto pair = [&](Point2 q, double sq, double weight) {
      const Point2 d = difference(p, q, wrap);
      const double s2 = 0.5 * (width[i] * width[i] + sq * sq);
      const double r2 = d.x * d.x + d.y * d.y;
      if (r2 > kCutoff * kCutoff * s2) return;
      f = f + weight * std::exp(-r2 / (4 * s2)) * d;
    };
    const double reach = kCutoff * std::sqrt(0.5 * (width[i] * width[i] + widest * widest));
    auto other = [&](int j) {
      if (std::size_t(j) != i) pair(points[std::size_t(j)], width[std::size_t(j)], 1);
    };
    if (allPairs)
      for (std::size_t j = 0; j < n; ++j) other(int(j));
    else
      grid.near(p, reach, wrap, other);
    if (adaptive_) {
      auto sample = [&](int m) {
        pair(sample_[std::size_t(m)], sampleWidth_[std::size_t(m)], -sampleMass);
      };
      const double sampleReach =
          kCutoff * std::sqrt(0.5 * (width[i] * width[i] + sampleWidest * sampleWidest));
      if (allPairs)
        for (std::size_t m = 0; m < sample_.size(); ++m) sample(int(m));
      else
        sampleIndex_->grid.near(p, sampleReach, false, sample);
    } else if (!wrap) {
      // The square's pull: 2 N s^2 grad of int k_s(p - x) dx over it.
      const double h = 1 / (2 * s_);
      const double l = h * p.x, r = h * (1 - p.x), b = h * p.y, t = h * (1 - p.y);
      const double a = 2 * double(n) * s_ * s_ * s_ * std::sqrt(std::numbers::pi);
      f = f + Point2{a * (std::erf(b) + std::erf(t)) * (std::exp(-l * l) - std::exp(-r * r)),
                     a * (std::erf(l) + std::erf(r)) * (std::exp(-b * b) - std::exp(-t * t))};
    }
    out[i] = f;
  });
}

double GaussianBlueNoise::energy(std::span<const Point2> points) const {
  if (adaptive_) throw std::logic_error("gbn: energy() is for the uniform target");
  const bool wrap = settings_.boundary == BlueNoiseBoundary::Toroidal;
  const std::size_t n = points.size();
  double e = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const Point2 d = difference(points[i], points[j], wrap);
      e += 2 * s_ * s_ * std::exp(-(d.x * d.x + d.y * d.y) / (4 * s_ * s_));
    }
  if (wrap) return e;
  const double sq = s_ * std::sqrt(std::numbers::pi), h = 1 / (2 * s_);
  for (const Point2 &p : points) {
    const double ix = sq * (std::erf(h * p.x) + std::erf(h * (1 - p.x)));
    const double iy = sq * (std::erf(h * p.y) + std::erf(h * (1 - p.y)));
    e -= 2 * double(n) * s_ * s_ * ix * iy;
  }
  return e;
}

void GaussianBlueNoise::optimize(std::span<Point2> points,
                                 const std::function<void(int)> &progress) const {
  if (points.size() != n_)
    throw std::invalid_argument("gbn: built for " + std::to_string(n_) + " points, the set has " +
                                std::to_string(points.size()));
  const bool wrap = settings_.boundary == BlueNoiseBoundary::Toroidal;
  // The authors' step, reduced for sigma > 1 as theirs is.
  const double step = settings_.step / std::max(1.0, settings_.sigma * settings_.sigma);
  std::vector<Point2> f(points.size());
  std::vector<double> width(points.size());
  const double top = std::nextafter(1.0, 0.0);
  for (int it = 0; it < settings_.iterations; ++it) {
    for (std::size_t i = 0; i < points.size(); ++i) width[i] = widthAt(points[i]);
    forces(points, width, f);
    for (std::size_t i = 0; i < points.size(); ++i) {
      // A trust region: no point moves more than half its kernel width per
      // iteration. Where widths vary (a peaked target) the authors' step
      // otherwise overshoots and sets blow up; converged sets, whose moves
      // are far smaller, are unchanged by it.
      Point2 move = step * f[i];
      const double length = std::hypot(move.x, move.y), limit = 0.5 * width[i];
      if (length > limit) move = (limit / length) * move;
      const Point2 p = points[i] + move;
      points[i] = wrap ? Point2{wrapUnit(p.x), wrapUnit(p.y)}
                       : Point2{std::clamp(p.x, 0.0, top), std::clamp(p.y, 0.0, top)};
    }
    if (progress) progress(it + 1);
  }
}

}  // namespace nuld
