#include "sampler/bluenoise/sliced_ot.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "sampler/bluenoise/target_sample.h"
#include "sampler/io/round_trip.h"
#include "sampler/sequences/rng.h"

namespace nuld {
namespace {

// The inverse CDF of a X + b Y, X, Y uniform on [0, 1], 0 <= a <= b, b > 0:
// its density rises on [0, a], is flat on [a, b] and falls on [b, a + b].
double trapezoidQuantile(double a, double b, double p) {
  if (p <= a / (2 * b)) return std::sqrt(2 * a * b * p);
  if (p <= 1 - a / (2 * b)) return p * b + a / 2;
  return a + b - std::sqrt(2 * a * b * (1 - p));
}

// The first moment of that distribution below u: G(u) = int_0^u t f(t) dt.
double trapezoidPartialMean(double a, double b, double u) {
  u = std::clamp(u, 0.0, a + b);
  if (u <= a) return a > 0 ? u * u * u / (3 * a * b) : 0.0;
  const double atA = a * a / (3 * b);
  if (u <= b) return atA + (u * u - a * a) / (2 * b);
  const double atB = atA + (b * b - a * a) / (2 * b);
  auto antiderivative = [&](double t) { return (a + b) * t * t / 2 - t * t * t / 3; };
  return atB + (antiderivative(u) - antiderivative(b)) / (a * b);
}

// The uniform disc of radius R centred at 0, projected on any direction:
// its CDF and the first moment below t, int_-R^t s f(s) ds.
constexpr double kDiscRadius = 0.5;
double discProjectionCdf(double t) {
  const double R = kDiscRadius;
  t = std::clamp(t, -R, R);
  return 0.5 +
         (t * std::sqrt(R * R - t * t) + R * R * std::asin(t / R)) / (std::numbers::pi * R * R);
}
double discPartialMean(double t) {
  const double R = kDiscRadius;
  t = std::clamp(t, -R, R);
  return -2 / (3 * std::numbers::pi * R * R) * std::pow(R * R - t * t, 1.5);
}
// The quantile by bisection: the CDF is increasing and cheap, and 64 halvings
// of [-R, R] reach double precision.
double discProjectionQuantile(double p) {
  double lo = -kDiscRadius, hi = kDiscRadius;
  for (int i = 0; i < 64; ++i) {
    const double mid = 0.5 * (lo + hi);
    (discProjectionCdf(mid) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

void uniformDiscSlabMeans(std::span<double> out) {
  const std::size_t n = out.size();
  double below = 0;  // the first moment below the slab's lower end
  for (std::size_t k = 0; k < n; ++k) {
    const double upper =
        k + 1 == n ? kDiscRadius : discProjectionQuantile(double(k + 1) / double(n));
    const double g = discPartialMean(upper);
    out[k] = (g - below) * double(n);
    below = g;
  }
}

Point2 squareToDisc(Point2 u) {
  const double a = 2 * u.x - 1, b = 2 * u.y - 1;
  if (a == 0 && b == 0) return {0.5, 0.5};
  constexpr double quarter = std::numbers::pi / 4;
  const bool wide = std::abs(a) > std::abs(b);
  const double r = wide ? a : b, phi = wide ? quarter * (b / a) : 2 * quarter - quarter * (a / b);
  return {0.5 + kDiscRadius * r * std::cos(phi), 0.5 + kDiscRadius * r * std::sin(phi)};
}

Point2 discToSquare(Point2 p) {
  const double x = (p.x - 0.5) / kDiscRadius, y = (p.y - 0.5) / kDiscRadius;
  const double r = std::min(std::hypot(x, y), 1.0);
  constexpr double quarter = std::numbers::pi / 4;
  double phi = std::atan2(y, x);
  if (phi < -quarter) phi += 8 * quarter;  // [-pi/4, 7 pi/4): the four wedges in turn
  double a, b;
  if (phi < quarter) {  // right: a = r
    a = r, b = r * phi / quarter;
  } else if (phi < 3 * quarter) {  // top: b = r
    b = r, a = r * (2 * quarter - phi) / quarter;
  } else if (phi < 5 * quarter) {  // left: a = -r
    a = -r, b = -r * (phi - 4 * quarter) / quarter;
  } else {  // bottom: b = -r
    b = -r, a = -r * (6 * quarter - phi) / quarter;
  }
  const double below1 = std::nextafter(1.0, 0.0);
  return {std::clamp((a + 1) / 2, 0.0, below1), std::clamp((b + 1) / 2, 0.0, below1)};
}

std::size_t SlicedOtSettings::samplesFor(std::size_t n) const {
  return targetSamples > 0 ? targetSamples : std::max<std::size_t>(64 * n, 16384);
}

std::string SlicedOtSettings::describe() const {
  std::ostringstream s;
  s << "iterations=" << iterations << " slices=" << slices << " step=" << formatRoundTrip(step)
    << " target_samples=" << targetSamples << " seed=" << seed
    << " uniform_domain=" << toString(uniformDomain);
  return s.str();
}

void SlicedOtSettings::validate() const {
  auto bad = [](const std::string &what) { throw std::invalid_argument("sot: " + what); };
  if (iterations < 0 || iterations > 10000000) bad("iterations must be in [0, 10^7]");
  if (slices < 1 || slices > 65536) bad("slices must be in [1, 65536]");
  if (!(step > 0 && step <= 2)) bad("step must be in (0, 2]");
  if (targetSamples > (std::size_t(1) << 26)) bad("target samples must be at most 2^26");
}

void uniformProjectionSlabMeans(Point2 theta, std::span<double> out) {
  // theta . X = lowest + a X' + b Y' with a <= b the sorted |components|.
  const double lowest = std::min(0.0, theta.x) + std::min(0.0, theta.y);
  const double a = std::min(std::abs(theta.x), std::abs(theta.y));
  const double b = std::max(std::abs(theta.x), std::abs(theta.y));
  const std::size_t n = out.size();
  double below = 0;  // G at the slab's lower end
  for (std::size_t k = 0; k < n; ++k) {
    const double upper = k + 1 == n ? a + b : trapezoidQuantile(a, b, double(k + 1) / double(n));
    const double g = trapezoidPartialMean(a, b, upper);
    out[k] = lowest + (g - below) * double(n);
    below = g;
  }
}

SliceDestinations::SliceDestinations(const Target &target, const SlicedOtSettings &settings,
                                     std::size_t n)
    : uniform_(target.isUniform()),
      disc_(uniform_ && settings.uniformDomain == UniformSotDomain::Disc),
      n_(n) {
  settings.validate();
  if (n == 0) throw std::invalid_argument("sot: a set needs at least one point");
  if (disc_) {
    table_.resize(n);
    uniformDiscSlabMeans(table_);
  }
  if (uniform_) return;
  const std::vector<Point2> sample =
      stratifiedTargetSample(target, settings.samplesFor(n), hash3(settings.seed, 0x50715A, n));
  constexpr int D = kSliceTableDirections;
  table_.resize(std::size_t(D) * n);
  // Block k of the sorted projections, samples [k M / N, (k + 1) M / N),
  // holds mass 1/N; its mean is where rank k goes.
  tbb::parallel_for(0, D, [&](int d) {
    const double angle = std::numbers::pi * d / D;
    const Point2 theta{std::cos(angle), std::sin(angle)};
    std::vector<double> projected(sample.size());
    for (std::size_t j = 0; j < sample.size(); ++j)
      projected[j] = sample[j].x * theta.x + sample[j].y * theta.y;
    std::sort(projected.begin(), projected.end());
    const std::size_t m = projected.size();
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t lo = k * m / n, hi = std::max(lo + 1, (k + 1) * m / n);
      table_[std::size_t(d) * n + k] =
          std::accumulate(projected.begin() + std::ptrdiff_t(lo),
                          projected.begin() + std::ptrdiff_t(hi), 0.0) /
          double(hi - lo);
    }
  });
}

void SliceDestinations::along(Point2 theta, std::span<double> out) const {
  if (disc_) {
    // The disc's centre (1/2, 1/2) projects to (theta.x + theta.y) / 2.
    const double centre = 0.5 * (theta.x + theta.y);
    for (std::size_t k = 0; k < n_; ++k) out[k] = centre + table_[k];
    return;
  }
  if (uniform_) return uniformProjectionSlabMeans(theta, out);
  // Directions a half-turn apart see the same projections negated, in
  // reverse order: row D is row 0 mirrored.
  constexpr int D = kSliceTableDirections;
  double angle = std::atan2(theta.y, theta.x);
  bool flip = false;
  if (angle < 0) angle += std::numbers::pi, flip = true;
  const double at = std::min(angle / std::numbers::pi * D, double(D) - 1e-9);
  const int d = int(at);
  const double w = at - d;
  const std::size_t n = n_;
  const double *lo = &table_[std::size_t(d) * n];
  const double *hi = d + 1 < D ? &table_[std::size_t(d + 1) * n] : nullptr;
  for (std::size_t k = 0; k < n; ++k) {
    const double upper = hi ? hi[k] : -table_[n - 1 - k];
    out[k] = (1 - w) * lo[k] + w * upper;
  }
  if (flip) {
    std::reverse(out.begin(), out.end());
    for (double &v : out) v = -v;
  }
}

void slicedOtTransport(const SliceDestinations &destinations, const SlicedOtSettings &settings,
                       std::uint32_t instance, std::span<Point2> points,
                       const std::function<void(int)> &progress) {
  settings.validate();
  const std::size_t n = points.size();
  if (n != destinations.size())
    throw std::invalid_argument("sot: the destinations were built for " +
                                std::to_string(destinations.size()) + " points, the set has " +
                                std::to_string(n));
  std::vector<double> projection(n), goal(n);
  std::vector<std::size_t> order(n);
  std::vector<Point2> displacement(n);
  const bool disc = destinations.inDisc();
  if (disc)
    for (Point2 &p : points) p = squareToDisc(p);
  Rng rng(settings.seed, hash3(0x5107, instance, 0));
  for (int it = 0; it < settings.iterations; ++it) {
    std::fill(displacement.begin(), displacement.end(), Point2{0, 0});
    for (int s = 0; s < settings.slices; ++s) {
      const double angle = 2 * std::numbers::pi * rng.uniform();
      const Point2 theta{std::cos(angle), std::sin(angle)};
      for (std::size_t i = 0; i < n; ++i)
        projection[i] = points[i].x * theta.x + points[i].y * theta.y;
      std::iota(order.begin(), order.end(), std::size_t(0));
      std::sort(order.begin(), order.end(),
                [&](std::size_t a, std::size_t b) { return projection[a] < projection[b]; });
      destinations.along(theta, goal);
      for (std::size_t k = 0; k < n; ++k) {
        const std::size_t i = order[k];
        displacement[i] = displacement[i] + (goal[k] - projection[i]) * theta;
      }
    }
    const double scale = settings.step / settings.slices;
    for (std::size_t i = 0; i < n; ++i) {
      const Point2 p = points[i] + scale * displacement[i];
      if (disc) {
        // Back onto the disc's edge along the ray from its centre.
        const Point2 d = p - Point2{0.5, 0.5};
        const double r = std::hypot(d.x, d.y);
        points[i] = r > kDiscRadius ? Point2{0.5, 0.5} + (kDiscRadius / r) * d : p;
        continue;
      }
      // Inside the square: the largest double below 1 bounds it above.
      points[i] = {std::clamp(p.x, 0.0, std::nextafter(1.0, 0.0)),
                   std::clamp(p.y, 0.0, std::nextafter(1.0, 0.0))};
    }
    if (progress) progress(it + 1);
  }
  if (disc)
    for (Point2 &p : points) p = discToSquare(p);
}

}  // namespace nuld
