#include "sampler/targets/basic_targets.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "sampler/io/round_trip.h"
#include "sampler/targets/invert_1d.h"

namespace nuld {
namespace {

double clamp01(double x) { return std::clamp(x, 0.0, 1.0); }
// Avoids infinite Jacobians where the density vanishes on the boundary.
constexpr double kTinyDensity = 1e-12;

std::string formatSpec(const std::string &name, std::initializer_list<double> values) {
  std::string s = name;
  char separator = ':';
  for (double v : values) {
    s += separator + formatRoundTrip(v);
    separator = ',';
  }
  return s;
}

// Samples the linear density c0 (1 - x) + c1 x on [0, 1] (c0, c1 >= 0).
double sampleLinear(double c0, double c1, double u) {
  const double total = 0.5 * (c0 + c1);
  if (total <= 0) return u;
  const double t = u * total;
  if (t <= 0) return 0;
  const double x = 2 * t / (c0 + std::sqrt(std::max(0.0, c0 * c0 + 2 * (c1 - c0) * t)));
  return std::min(x, 1.0);
}

}  // namespace

double UniformTarget::pdf(Point2 p) const { return inUnitSquare(p) ? 1.0 : 0.0; }

// ---------------------------------------------------------------- bilinear

BilinearTarget::BilinearTarget(double w00, double w10, double w01, double w11)
    : spec_{w00, w10, w01, w11}, w_{w00, w10, w01, w11} {
  for (double w : w_)
    if (!(w >= 0) || !std::isfinite(w))
      throw std::invalid_argument("bilinear target: weights must be finite and >= 0");
  const double largest = *std::max_element(w_.begin(), w_.end());
  if (largest <= 0) throw std::invalid_argument("bilinear target: all weights are zero");
  if (largest < std::numeric_limits<double>::min())
    throw std::invalid_argument(
        "bilinear target: the largest weight, " + formatRoundTrip(largest) +
        ", underflows (below 2.2e-308); only the weights' ratios matter, so scale them up");
  // Scale-free: far from 1 the weights are replaced by their ratios to the
  // largest, so tiny ones do not underflow in the inverse nor huge ones
  // overflow in the sums (ordinary weights are kept as given, bit for bit).
  if (largest < 1e-100 || largest > 1e100)
    for (double &w : w_) w /= largest;
  norm_ = 0.25 * (w_[0] + w_[1] + w_[2] + w_[3]);
}

std::string BilinearTarget::spec() const {
  return formatSpec("bilinear", {spec_[0], spec_[1], spec_[2], spec_[3]});
}

double BilinearTarget::pdf(Point2 p) const {
  if (!inUnitSquare(p)) return 0;
  const double f = w_[0] * (1 - p.x) * (1 - p.y) + w_[1] * p.x * (1 - p.y) +
                   w_[2] * (1 - p.x) * p.y + w_[3] * p.x * p.y;
  return f / norm_;
}

double BilinearTarget::mass(const Box2 &box) const {
  const Box2 b = box.clipped();
  if (b.area() <= 0) return 0;
  // Integrals of the hat functions (1 - t) and t over [lo, hi].
  auto lower = [](double lo, double hi) { return (hi - 0.5 * hi * hi) - (lo - 0.5 * lo * lo); };
  auto upper = [](double lo, double hi) { return 0.5 * (hi * hi - lo * lo); };
  const double x0 = lower(b.lo.x, b.hi.x), x1 = upper(b.lo.x, b.hi.x);
  const double y0 = lower(b.lo.y, b.hi.y), y1 = upper(b.lo.y, b.hi.y);
  return std::max(0.0,
                  (w_[0] * x0 * y0 + w_[1] * x1 * y0 + w_[2] * x0 * y1 + w_[3] * x1 * y1) / norm_);
}

Inversion BilinearTarget::invert(Point2 u) const {
  // Marginal in x is linear from a (at x = 0) to b (at x = 1).
  const double a = 0.5 * (w_[0] + w_[2]), b = 0.5 * (w_[1] + w_[3]);
  const double x = sampleLinear(a, b, clamp01(u.x));
  const double gx = std::max(a * (1 - x) + b * x, kTinyDensity * norm_);
  // Conditional in y given x is linear from c0 to c1.
  const double c0 = w_[0] * (1 - x) + w_[1] * x, c1 = w_[2] * (1 - x) + w_[3] * x;
  const double y = sampleLinear(c0, c1, clamp01(u.y));
  const double zc = 0.5 * (c0 + c1);
  Inversion out;
  out.x = {x, y};
  auto &J = out.jacobian.m;
  J[0][0] = norm_ / gx;
  J[0][1] = 0;
  if (zc <= 0) {  // the whole column has zero density: y = u.y
    J[1][0] = 0;
    J[1][1] = 1;
    return out;
  }
  const double hy = std::max(c0 * (1 - y) + c1 * y, kTinyDensity * zc);
  J[1][1] = zc / hy;
  // Implicit differentiation of G(y, x) = u.y, G the conditional CDF.
  const double dc0 = w_[1] - w_[0], dc1 = w_[3] - w_[2], dzc = 0.5 * (dc0 + dc1);
  const double dGdx = (dc0 * y + 0.5 * (dc1 - dc0) * y * y) / zc - clamp01(u.y) * dzc / zc;
  const double dydx = -dGdx / (hy / zc);
  J[1][0] = dydx * J[0][0];
  return out;
}

// ---------------------------------------------------------------- gaussian

namespace {
// Standard normal mass of [a, b], accurate in both tails and near the mean:
// erfc differences in the tails, erf differences elsewhere (erfc values near
// 1 would cancel there).
double normalInterval(double a, double b) {
  if (b <= a) return 0;
  constexpr double r = std::numbers::sqrt2;
  if (a >= 1) return 0.5 * (std::erfc(a / r) - std::erfc(b / r));
  if (b <= -1) return 0.5 * (std::erfc(-b / r) - std::erfc(-a / r));
  return 0.5 * (std::erf(b / r) - std::erf(a / r));
}
}  // namespace

double GaussianTarget::Axis::massBelow(double x) const {
  return normalInterval(-mean / sigma, (std::clamp(x, 0.0, 1.0) - mean) / sigma);
}

double GaussianTarget::Axis::pdf(double x) const {
  if (x < 0 || x > 1) return 0;
  const double t = (x - mean) / sigma;
  return std::exp(-0.5 * t * t) / (sigma * std::sqrt(2 * std::numbers::pi) * total);
}

double GaussianTarget::Axis::inverse(double u) const {
  const double t = clamp01(u) * total;
  return invertMonotone([&](double x) { return massBelow(x); },
                        [&](double x) { return pdf(x) * total; }, t, 0.0, 1.0);
}

GaussianTarget::GaussianTarget(double mx, double my, double sigma)
    : ax_{mx, sigma, 0}, ay_{my, sigma, 0} {
  if (!(sigma > 0) || !std::isfinite(sigma) || !std::isfinite(mx) || !std::isfinite(my))
    throw std::invalid_argument("gaussian target: expected finite mean and sigma > 0");
  if (sigma < kMinSigma)
    throw std::invalid_argument("gaussian target: sigma " + formatRoundTrip(sigma) +
                                " is below 1e-12: the points would be the mean to double "
                                "precision and the density overflows");
  ax_.total = ax_.massBelow(1);
  ay_.total = ay_.massBelow(1);
  if (!(ax_.total > 1e-300 && ay_.total > 1e-300))
    throw std::invalid_argument("gaussian target: no mass inside the unit square");
}

std::string GaussianTarget::spec() const {
  return formatSpec("gaussian", {ax_.mean, ay_.mean, ax_.sigma});
}

double GaussianTarget::pdf(Point2 p) const { return ax_.pdf(p.x) * ay_.pdf(p.y); }

double GaussianTarget::mass(const Box2 &box) const {
  const Box2 b = box.clipped();
  if (b.area() <= 0) return 0;
  const double mx =
      normalInterval((b.lo.x - ax_.mean) / ax_.sigma, (b.hi.x - ax_.mean) / ax_.sigma);
  const double my =
      normalInterval((b.lo.y - ay_.mean) / ay_.sigma, (b.hi.y - ay_.mean) / ay_.sigma);
  return mx / ax_.total * (my / ay_.total);
}

Inversion GaussianTarget::invert(Point2 u) const {
  Inversion out;
  out.x = {ax_.inverse(u.x), ay_.inverse(u.y)};
  out.jacobian.m[0][0] = 1 / std::max(ax_.pdf(out.x.x), kTinyDensity);
  out.jacobian.m[1][1] = 1 / std::max(ay_.pdf(out.x.y), kTinyDensity);
  return out;
}

// ---------------------------------------------------------------- quarter disc

namespace {
constexpr double kDiscDensity = 4 / std::numbers::pi;

// Integral of sqrt(1 - t^2) over [0, x], x in [0, 1].
double discColumnIntegral(double x) {
  return 0.5 * (x * std::sqrt(std::max(0.0, 1 - x * x)) + std::asin(x));
}

// Area of the disc intersected with [0, a] x [0, b], a, b in [0, 1].
double discCornerArea(double a, double b) {
  if (a <= 0 || b <= 0) return 0;
  const double xc = std::sqrt(std::max(0.0, 1 - b * b));  // circle meets y = b
  if (a <= xc) return a * b;
  return b * xc + discColumnIntegral(a) - discColumnIntegral(xc);
}
}  // namespace

double QuarterDiscTarget::pdf(Point2 p) const {
  return inUnitSquare(p) && p.x * p.x + p.y * p.y <= 1 ? kDiscDensity : 0.0;
}

double QuarterDiscTarget::mass(const Box2 &box) const {
  const Box2 b = box.clipped();
  if (b.area() <= 0) return 0;
  const double area = discCornerArea(b.hi.x, b.hi.y) - discCornerArea(b.lo.x, b.hi.y) -
                      discCornerArea(b.hi.x, b.lo.y) + discCornerArea(b.lo.x, b.lo.y);
  return std::max(0.0, kDiscDensity * area);
}

namespace {
// x with discColumnIntegral(x) = t: Newton safeguarded by bisection, started
// inside a bracket read from a table of the inverse at evenly spaced t, so
// that a few steps suffice (the neural generator inverts every point it
// makes). The table holds converged inversions, so the bracket holds the
// root up to rounding.
double invertDiscColumn(double t) {
  constexpr int kEntries = 256;
  constexpr double kTotal = std::numbers::pi / 4;
  auto column = [](double s) { return std::sqrt(std::max(0.0, 1 - s * s)); };
  static const std::array<double, kEntries + 1> table = [&] {
    std::array<double, kEntries + 1> x{};
    for (int k = 0; k <= kEntries; ++k)
      x[k] = invertMonotone(discColumnIntegral, column, kTotal * k / kEntries, 0.0, 1.0);
    return x;
  }();
  const double s = std::clamp(t / kTotal, 0.0, 1.0) * kEntries;
  const int k = std::min(int(s), kEntries - 1);
  const double lo = table[k], hi = table[k + 1];
  return invertMonotone(discColumnIntegral, column, t, lo, hi, lo + (s - k) * (hi - lo));
}
}  // namespace

Inversion QuarterDiscTarget::invert(Point2 u) const {
  const double x = invertDiscColumn(clamp01(u.x) * (std::numbers::pi / 4));
  const double h = std::max(std::sqrt(std::max(0.0, 1 - x * x)), kTinyDensity);
  Inversion out;
  out.x = {x, clamp01(u.y) * h};
  auto &J = out.jacobian.m;
  J[0][0] = 1 / (kDiscDensity * h);  // 1 / marginal pdf
  J[0][1] = 0;
  J[1][0] = clamp01(u.y) * (-x / h) * J[0][0];
  J[1][1] = h;
  return out;
}

// ---------------------------------------------------------------- step

StepTarget::StepTarget(double x0, double left, double right) : x0_(x0), left_(left), right_(right) {
  if (!(x0 >= 0 && x0 <= 1)) throw std::invalid_argument("step target: x0 must lie in [0, 1]");
  if (!(left >= 0 && right >= 0) || !std::isfinite(left) || !std::isfinite(right))
    throw std::invalid_argument("step target: weights must be finite and >= 0");
  norm_ = left * x0 + right * (1 - x0);
  if (!(norm_ > 0)) throw std::invalid_argument("step target: zero total mass");
}

std::string StepTarget::spec() const { return formatSpec("step", {x0_, left_, right_}); }

double StepTarget::massBelow(double x) const {
  x = clamp01(x);
  return left_ * std::min(x, x0_) + right_ * std::max(0.0, x - x0_);
}

double StepTarget::pdf(Point2 p) const {
  if (!inUnitSquare(p)) return 0;
  return (p.x < x0_ ? left_ : right_) / norm_;
}

double StepTarget::mass(const Box2 &box) const {
  const Box2 b = box.clipped();
  if (b.area() <= 0) return 0;
  return (massBelow(b.hi.x) - massBelow(b.lo.x)) * (b.hi.y - b.lo.y) / norm_;
}

Inversion StepTarget::invert(Point2 u) const {
  const double t = clamp01(u.x) * norm_;
  const double leftMass = left_ * x0_;
  double x;
  if (t < leftMass)
    x = t / left_;
  else
    x = right_ > 0 ? std::min(1.0, x0_ + (t - leftMass) / right_) : x0_;
  const double density = std::max(x < x0_ ? left_ : right_, kTinyDensity * norm_);
  Inversion out;
  out.x = {x, clamp01(u.y)};
  out.jacobian.m[0][0] = norm_ / density;
  return out;
}

}  // namespace nuld
