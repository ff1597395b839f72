#include "sampler/sequences/lattice.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

#include "sampler/sequences/rng.h"

namespace nuld {
namespace {

struct Vec {
  std::int64_t x, y;
  std::int64_t dot(Vec o) const { return x * o.x + y * o.y; }
  std::int64_t norm2() const { return dot(*this); }
};

// round(p / q) for q > 0, halves away from minus infinity, in integers.
std::int64_t roundDiv(std::int64_t p, std::int64_t q) {
  const std::int64_t t = 2 * p + q, d = 2 * q;
  return t >= 0 ? t / d : -((-t + d - 1) / d);
}

std::uint32_t checkedSize(std::size_t n) {
  if (n > 0xffffffffull)
    throw std::invalid_argument("lattice: " + std::to_string(n) +
                                " points; at most 2^32 - 1 are supported");
  return static_cast<std::uint32_t>(n);
}

// The searched generator (see latticeGenerator).
std::uint32_t searchGenerator(std::uint32_t n) {
  std::uint32_t best = 1;
  std::uint64_t bestLength = 0;
  for (std::uint32_t g = 1; g < n; ++g) {
    if (std::gcd(g, n) != 1) continue;  // not projection-regular (latticeGenerator)
    if (const std::uint64_t l = latticeShortestVector2(n, g); l > bestLength) {
      best = g;
      bestLength = l;
    }
  }
  return best;
}

}  // namespace

std::uint32_t goldenRatioGenerator(std::uint32_t n) {
  if (n <= 2) return n == 2 ? 1 : 0;
  constexpr double kInvPhi2 = 0.38196601125010515180;  // 1 / phi^2 = 2 - phi
  const auto g0 = static_cast<std::int64_t>(double(n) * kInvPhi2 + 0.5);
  for (std::int64_t step = 0;; ++step)
    for (const std::int64_t g : {g0 - step, g0 + step})
      if (g >= 1 && g < n && std::gcd(std::uint64_t(g), std::uint64_t(n)) == 1)
        return static_cast<std::uint32_t>(g);
}

std::uint64_t latticeShortestVector2(std::uint32_t n, std::uint32_t g) {
  // Lagrange's reduction: subtract the nearest multiple of the shorter
  // vector from the longer until the longer one stops being the shorter.
  Vec a{0, std::int64_t(n)}, b{1, std::int64_t(g)};
  if (a.norm2() < b.norm2()) std::swap(a, b);
  for (;;) {
    const std::int64_t mu = roundDiv(a.dot(b), b.norm2());
    a = {a.x - mu * b.x, a.y - mu * b.y};
    if (a.norm2() >= b.norm2()) return std::uint64_t(b.norm2());
    std::swap(a, b);
  }
}

std::uint32_t latticeGenerator(std::size_t size) {
  const std::uint32_t n = checkedSize(size);
  if (n <= 2) return n == 2 ? 1 : 0;
  if (n > kMaxSearchedLattice) return goldenRatioGenerator(n);
  // g + 1 by N, 0 until searched. A race searches twice and stores the same
  // value, so relaxed loads and stores suffice and readers never wait.
  static std::array<std::atomic<std::uint32_t>, kMaxSearchedLattice + 1> cache{};
  std::uint32_t stored = cache[n].load(std::memory_order_relaxed);
  if (stored == 0) {
    stored = searchGenerator(n) + 1;
    cache[n].store(stored, std::memory_order_relaxed);
  }
  return stored - 1;
}

void rank1Lattice(std::span<Point2> out) {
  const std::uint32_t n = checkedSize(out.size());
  const std::uint64_t g = latticeGenerator(n);
  // frac(i g / N) exactly: (i g) mod N in integers (i, g < 2^32).
  for (std::uint32_t i = 0; i < n; ++i) out[i] = {double(i) / n, double((i * g) % n) / n};
}

void latticeSet(std::uint64_t seed, std::span<Point2> out) {
  rank1Lattice(out);
  Rng rng(seed, 0x1a77);
  const Point2 shift{rng.uniform(), rng.uniform()};
  for (Point2 &p : out) p = {wrapUnit(p.x + shift.x), wrapUnit(p.y + shift.y)};
  shuffle(out, rng);
}

double bakerFold(double x) { return std::min(1 - std::fabs(2 * x - 1), std::nextafter(1.0, 0.0)); }

void latticeBakerSet(std::uint64_t seed, std::span<Point2> out) {
  latticeSet(seed, out);
  for (Point2 &p : out) p = {bakerFold(p.x), bakerFold(p.y)};
}

}  // namespace nuld
