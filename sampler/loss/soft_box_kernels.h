#pragma once
// The two pair kernels of the soft box loss (sampler/loss/soft_box_loss.cpp,
// the only file that includes this one): DirectKernel evaluates
// sigma(alpha d) from the definition, FactoredKernel from per-point and
// per-box exponential factors (docs/architecture.md, "The soft box loss").
// Both give the same values to the kernel contract's 1e-12 (tested).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <type_traits>
#include <vector>

#include "sampler/loss/lanes.h"
#include "sampler/loss/point_grid.h"
#include "sampler/point.h"

namespace nuld::soft_box {

// sigma(alpha d) and its slope for a vector of points.
struct PairLanes {
  lanes::Doubles value, slopeX, slopeY;
};

// What a kernel reads for the points of one storage order: the coordinates
// (DirectKernel) or their exponentials (FactoredKernel), each array followed
// by readable slack.
struct PointColumns {
  const double *c0 = nullptr, *c1 = nullptr, *c2 = nullptr, *c3 = nullptr;
  const std::int64_t *tileX = nullptr, *tileY = nullptr;  // FactoredKernel's tiles
};

// The definition: d = the smallest signed distance to the box's sides,
// sigma(alpha d) through one exp of -|alpha d| per pair. Reads x and y.
class DirectKernel {
 public:
  // What every box of one call shares.
  struct Scale {
    double alpha, cutoff;
  };

  DirectKernel(const Box2 &A, const Scale &scale)
      : loX_(lanes::broadcast(A.lo.x)),
        hiX_(lanes::broadcast(A.hi.x)),
        loY_(lanes::broadcast(A.lo.y)),
        hiY_(lanes::broadcast(A.hi.y)),
        alpha_(lanes::broadcast(scale.alpha)),
        cutoff_(lanes::broadcast(scale.cutoff)) {}

  // Which of a vector of points lie in the band, and which deep inside.
  struct Classified {
    lanes::Doubles x, y;
    lanes::Mask band, inside;
  };
  Classified classify(const PointColumns &p, std::uint32_t k) const {
    using lanes::Doubles;
    const Doubles x = lanes::load(p.c0 + k), y = lanes::load(p.c1 + k);
    const Doubles dX = lanes::min(x - loX_, hiX_ - x), dY = lanes::min(y - loY_, hiY_ - y);
    const Doubles at = alpha_ * lanes::min(dX, dY);
    return {x, y, lanes::abs(at) <= cutoff_, at > cutoff_};
  }

  PairLanes evaluate(const PointColumns &p, std::uint32_t k, bool wantSlope) const {
    using lanes::Doubles;
    const Doubles x = lanes::load(p.c0 + k), y = lanes::load(p.c1 + k);
    const Doubles zero{}, one = lanes::broadcast(1.0);
    const Doubles toLoX = x - loX_, toHiX = hiX_ - x, toLoY = y - loY_, toHiY = hiY_ - y;
    const Doubles dX = lanes::min(toLoX, toHiX), dY = lanes::min(toLoY, toHiY);
    const Doubles at = alpha_ * lanes::min(dX, dY);
    const Doubles a = lanes::min(lanes::abs(at), cutoff_);
    const Doubles e = lanes::exp(-a);
    const Doubles inv = 1.0 / (1.0 + e);
    const lanes::Mask band = lanes::abs(at) <= cutoff_;
    PairLanes out{};
    out.value = at > cutoff_ ? one : (band ? (at >= 0 ? inv : e * inv) : zero);
    if (!wantSlope) return out;
    // The nearest side, ties to the first of lo x, hi x, lo y, hi y.
    const Doubles ds = band ? e * inv * inv : zero;
    const lanes::Mask onX = dX <= dY;
    out.slopeX = onX ? (toLoX <= toHiX ? ds : -ds) : zero;
    out.slopeY = onX ? zero : (toLoY <= toHiY ? ds : -ds);
    return out;
  }

 private:
  lanes::Doubles loX_, hiX_, loY_, hiY_, alpha_, cutoff_;
};

// The same sigma without an exp per pair. exp(-alpha d) is the largest of
// exp(-alpha (x - lo.x)) and its three siblings, and each factors through a
// reference c near the point: exp(-alpha (x - c)) exp(alpha (lo.x - c)), a
// per-point and a per-box exponential; then sigma(alpha d) = 1 / (1 + that)
// on either side of the box. The references are the centres of kTiles x
// kTiles tiles of the unit square, so a point's factors stay within
// e^(alpha / 2 kTiles) and a box's, for the tiles near a side, within
// e^(alpha / 2 kTiles + cutoff); factors for tiles far from a side saturate
// at e^(+-700), which only ever makes a product lie further beyond the
// cutoff, where sigma is 0 or 1 anyway. Rounding moves the exponent by up to
// alpha / 2 kTiles ulps, about 4e-14 relative per pair at the largest alpha
// allowed, far inside the kernel's 1e-12 contract. Pairs beyond the cutoff
// get 1 / (1 + E) instead of an exact 0 or 1: within e^-36 of it, as the
// cutoff itself allows; their slopes are exactly 0, as DirectKernel's.
//
// No product is subnormal (x86 cores compute those through microcode
// assists, a large slowdown at high alpha:
// tools/experiments/optimizer_speed.md, "Subnormal products"): a box side at
// -inf or +inf (multiple-corner boxes have two) has the factor 0, and a
// finite side's factors are floored at e^(alpha / 2 kTiles - 707), where a
// product with any point's factor is still a normal number and, for alpha
// up to 8 (707 - cutoff), still beyond the cutoff. Zero slopes beyond the
// cutoff keep the gradient's products normal too.
class FactoredKernel {
 public:
  static constexpr int kTiles = 8;  // per axis: one AVX-512 vector of a box's factors per side

  // Whether points in the unit square keep every relevant factor finite.
  static bool applies(double alpha, double cutoff) {
    return alpha / (2.0 * kTiles) + cutoff <= 700.0;
  }
  // The tile of a coordinate in [0, 1].
  static int tileOf(double t) { return std::clamp(int(t * kTiles), 0, kTiles - 1); }
  static double tileCentre(int tile) { return (tile + 0.5) / kTiles; }

  // What every box of one call shares, computed once per call.
  struct Scale {
    double alpha;
    double floorExponent;           // of the box factors (see above)
    lanes::Doubles bandLo, bandHi;  // e^-cutoff, e^cutoff: E outside them has no slope

    Scale(double alpha, double cutoff)
        : alpha(alpha),
          bandLo(lanes::broadcast(std::exp(-cutoff))),
          bandHi(lanes::broadcast(std::exp(cutoff))) {
      const double pointSpan = alpha / (2.0 * kTiles);
      floorExponent = 2 * pointSpan - 707 <= -cutoff ? pointSpan - 707 : -700.0;
    }
  };

  FactoredKernel(const Box2 &A, const Scale &scale) : scale_(scale) {
    const lanes::Doubles a = lanes::broadcast(scale.alpha);
    const lanes::Doubles floor = lanes::broadcast(scale.floorExponent);
    // exp(alpha (side - c)) or exp(alpha (c - side)) per tile; 0 for a side
    // that is not there.
    const auto factors = [&](double side, bool absent, double sign, double *out) {
      for (int t0 = 0; t0 < kTiles; t0 += lanes::kWidth) {
        lanes::Doubles centre;
        for (int j = 0; j < lanes::kWidth; ++j) centre[j] = tileCentre(t0 + j);
        const lanes::Doubles exponent = sign * a * (lanes::broadcast(side) - centre);
        lanes::store(out + t0, absent ? lanes::Doubles{} : lanes::exp(lanes::max(exponent, floor)));
      }
    };
    constexpr double inf = std::numeric_limits<double>::infinity();
    factors(A.lo.x, A.lo.x == -inf, 1, loX_);
    factors(A.hi.x, A.hi.x == inf, -1, hiX_);
    factors(A.lo.y, A.lo.y == -inf, 1, loY_);
    factors(A.hi.y, A.hi.y == inf, -1, hiY_);
  }

  PairLanes evaluate(const PointColumns &p, std::uint32_t k, bool wantSlope) const {
    using lanes::Doubles;
    const lanes::Mask tileX = lanes::loadMask(p.tileX + k), tileY = lanes::loadMask(p.tileY + k);
    // exp(-alpha (x - lo.x)), exp(-alpha (hi.x - x)), and the same in y.
    const Doubles eLoX = lanes::load(p.c0 + k) * lanes::lookup8(loX_, tileX);
    const Doubles eHiX = lanes::load(p.c1 + k) * lanes::lookup8(hiX_, tileX);
    const Doubles eLoY = lanes::load(p.c2 + k) * lanes::lookup8(loY_, tileY);
    const Doubles eHiY = lanes::load(p.c3 + k) * lanes::lookup8(hiY_, tileY);
    const Doubles eX = lanes::max(eLoX, eHiX), eY = lanes::max(eLoY, eHiY);
    // Far outside the box the product may overflow; 1e300 keeps E * inv^2 finite.
    const Doubles e = lanes::min(lanes::max(eX, eY), lanes::broadcast(1e300));
    const Doubles inv = 1.0 / (1.0 + e);
    PairLanes out{};
    out.value = inv;
    if (!wantSlope) return out;
    const Doubles zero{};
    const lanes::Mask band = e >= scale_.bandLo && e <= scale_.bandHi;
    const Doubles ds = band ? e * inv * inv : zero;
    // The nearest side has the largest exponential; ties as DirectKernel's.
    const lanes::Mask onX = eX >= eY;
    out.slopeX = onX ? (eLoX >= eHiX ? ds : -ds) : zero;
    out.slopeY = onX ? zero : (eLoY >= eHiY ? ds : -ds);
    return out;
  }

 private:
  // Per tile: exp(alpha (lo.x - c)), exp(alpha (c - hi.x)), and in y.
  alignas(64) double loX_[kTiles], hiX_[kTiles], loY_[kTiles], hiY_[kTiles];
  const Scale &scale_;
};

// The per-point factors FactoredKernel reads, for n coordinates in one
// storage order and their slack.
struct Exponentials {
  std::vector<double> minusX, plusX, minusY, plusY;
  std::vector<std::int64_t> tileX, tileY;

  Exponentials(const double *xs, const double *ys, std::size_t n, double alpha) {
    const std::size_t padded = n + PointGrid::kSlack;
    for (auto *v : {&minusX, &plusX, &minusY, &plusY}) v->assign(padded, 0.0);
    tileX.assign(padded, 0);
    tileY.assign(padded, 0);
    for (std::size_t k = 0; k < padded; ++k) {
      tileX[k] = FactoredKernel::tileOf(xs[k]);
      tileY[k] = FactoredKernel::tileOf(ys[k]);
    }
    for (std::size_t k = 0; k + lanes::kWidth <= padded; k += lanes::kWidth) {
      lanes::Doubles cx, cy;
      for (int j = 0; j < lanes::kWidth; ++j) {
        cx[j] = FactoredKernel::tileCentre(int(tileX[k + j]));
        cy[j] = FactoredKernel::tileCentre(int(tileY[k + j]));
      }
      const lanes::Doubles ax = alpha * (lanes::load(xs + k) - cx);
      const lanes::Doubles ay = alpha * (lanes::load(ys + k) - cy);
      lanes::store(&minusX[k], lanes::exp(-ax));
      lanes::store(&plusX[k], lanes::exp(ax));
      lanes::store(&minusY[k], lanes::exp(-ay));
      lanes::store(&plusY[k], lanes::exp(ay));
    }
  }
  PointColumns columns() const {
    return {minusX.data(), plusX.data(), minusY.data(), plusY.data(), tileX.data(), tileY.data()};
  }
};

// Whether FactoredKernel applies: every point in the unit square, and alpha
// within its bound.
inline bool factorsRepresentable(std::span<const Point2> points, double alpha, double cutoff) {
  if (!FactoredKernel::applies(alpha, cutoff)) return false;
  return std::all_of(points.begin(), points.end(),
                     [](Point2 p) { return p.x >= 0 && p.x <= 1 && p.y >= 0 && p.y <= 1; });
}

}  // namespace nuld::soft_box
