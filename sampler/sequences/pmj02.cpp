#include "sampler/sequences/pmj02.h"

#include <array>
#include <mutex>
#include <stdexcept>
#include <string>

#include "sampler/sequences/owen_set.h"
#include "sampler/sequences/rng.h"

namespace nuld {
namespace {

// A sequence as 32-bit fixed-point coordinates, one array per coordinate:
// the integers Owen scrambling and digital shifts work on.
struct Pmj02Bits {
  std::vector<std::uint32_t> x, y;
};

// The d leading binary digits of v, d in [0, 32].
constexpr std::uint32_t leading(std::uint32_t v, int d) { return d == 0 ? 0 : v >> (32 - d); }

// Which elementary intervals of area 2^-level hold a point. Shape a has
// a x digits and level - a y digits: a 2^a x 2^(level-a) grid, 2^level
// cells per shape, level + 1 shapes.
class Strata {
 public:
  explicit Strata(int level) : level_(level), occupied_(std::size_t(level + 1) << level) {}

  void mark(std::uint32_t x, std::uint32_t y) {
    for (int a = 0; a <= level_; ++a) occupied_[cell(a, leading(x, a), leading(y, level_ - a))] = 1;
  }
  // The finest x strips (level digits) reachable from interval (a, ix, iy)
  // through free intervals of ever more x digits and fewer y digits: Pharr's
  // walk. Every interval a point in those strips (and in the y range the
  // walk started from) would fall in with a >= the start is free.
  void freeX(int a, std::uint32_t ix, std::uint32_t iy, std::vector<std::uint32_t> &out) const {
    if (occupied_[cell(a, ix, iy)]) return;
    if (a == level_) return out.push_back(ix);
    freeX(a + 1, 2 * ix, iy >> 1, out);
    freeX(a + 1, 2 * ix + 1, iy >> 1, out);
  }
  // The same towards the finest y strips (shape 0).
  void freeY(int a, std::uint32_t ix, std::uint32_t iy, std::vector<std::uint32_t> &out) const {
    if (occupied_[cell(a, ix, iy)]) return;
    if (a == 0) return out.push_back(iy);
    freeY(a - 1, ix >> 1, 2 * iy, out);
    freeY(a - 1, ix >> 1, 2 * iy + 1, out);
  }

 private:
  std::size_t cell(int a, std::uint32_t ix, std::uint32_t iy) const {
    return (std::size_t(a) << level_) + (std::size_t(iy) << a) + ix;
  }
  int level_;
  std::vector<std::uint8_t> occupied_;
};

// Makes points count..2 count - 1 of a sequence whose first count points
// exist: level = log2(2 count).
class Pass {
 public:
  Pass(Pmj02Bits &s, std::uint64_t seed, int level)
      : s_(s), seed_(seed), level_(level), strata_(level) {
    for (std::size_t i = 0; i < (std::size_t(1) << (level - 1)); ++i) strata_.mark(s.x[i], s.y[i]);
  }

  // Point i, in the sub-square (cx, cy) of side 2^-r, r = ceil(level / 2):
  // a free finest x strip and a free finest y strip, each uniform among its
  // walk's leaves (the walks cover every shape between them, so any pair of
  // leaves avoids every occupied interval), then uniform within the cell.
  void place(std::size_t i, std::uint32_t cx, std::uint32_t cy) {
    const int r = (level_ + 1) / 2, extra = 2 * r - level_;  // extra: 1 for odd levels
    xs_.clear();
    ys_.clear();
    strata_.freeX(r, cx, cy >> extra, xs_);
    strata_.freeY(level_ - r, cx >> extra, cy, ys_);
    if (xs_.empty() || ys_.empty())
      throw std::logic_error("pmj02: no free stratum for point " + std::to_string(i));
    Rng rng(seed_, i);
    const std::uint32_t fx = xs_[rng.uniformInt(std::uint32_t(xs_.size()))];
    const std::uint32_t fy = ys_[rng.uniformInt(std::uint32_t(ys_.size()))];
    s_.x[i] = (fx << (32 - level_)) | (rng.nextU32() >> level_);
    s_.y[i] = (fy << (32 - level_)) | (rng.nextU32() >> level_);
    strata_.mark(s_.x[i], s_.y[i]);
  }

 private:
  Pmj02Bits &s_;
  std::uint64_t seed_;
  int level_;
  Strata strata_;
  std::vector<std::uint32_t> xs_, ys_;
};

// Christensen et al.'s construction. From 4^j points (one per square of
// side 2^-j) to twice as many: each new point goes into the sub-square of
// side 2^-(j+1) diagonally opposite its parent's. Then to four times as
// many: the first 4^j points' two remaining sub-squares, the one beside
// (x flipped) for all of them or the one above (y flipped) for all, one
// coin per level (choosing per point would break the (0,2) property of the
// blocks between), and then the diagonal of those.
Pmj02Bits generateBits(std::uint64_t seed, int log2Count) {
  if (log2Count < 0 || log2Count > kPmj02MaxLog2)
    throw std::invalid_argument("pmj02: 2^" + std::to_string(log2Count) + " points; at most 2^" +
                                std::to_string(kPmj02MaxLog2));
  const std::size_t n = std::size_t(1) << log2Count;
  Pmj02Bits s{std::vector<std::uint32_t>(n), std::vector<std::uint32_t>(n)};
  Rng first(seed, 0);
  s.x[0] = first.nextU32();
  s.y[0] = first.nextU32();
  for (int level = 1; level <= log2Count; ++level) {
    const std::size_t count = std::size_t(1) << (level - 1);
    const int r = (level + 1) / 2;
    Pass pass(s, seed, level);
    const auto sub = [&](std::size_t i) {
      return std::array<std::uint32_t, 2>{leading(s.x[i], r), leading(s.y[i], r)};
    };
    if (level % 2 == 1) {
      for (std::size_t i = 0; i < count; ++i) pass.place(count + i, sub(i)[0] ^ 1, sub(i)[1] ^ 1);
      continue;
    }
    const std::size_t q = count / 2;
    const std::uint32_t flipX = hash3(seed, level, 0x5b) & 1, flipY = flipX ^ 1;
    for (std::size_t i = 0; i < q; ++i) pass.place(count + i, sub(i)[0] ^ flipX, sub(i)[1] ^ flipY);
    for (std::size_t i = 0; i < q; ++i)
      pass.place(count + q + i, sub(i)[0] ^ flipY, sub(i)[1] ^ flipX);
  }
  return s;
}

int log2Ceil(std::size_t n) {
  int k = 0;
  while ((std::size_t(1) << k) < n) ++k;
  return k;
}

// Base b of 2^log2Count points, made once by whichever thread asks first.
const Pmj02Bits &cachedBase(int log2Count, unsigned b) {
  struct Slot {
    std::once_flag once;
    Pmj02Bits bits;
  };
  static std::array<std::array<Slot, kPmj02Bases>, 17> slots;
  static_assert(kPmj02MaxSet == std::size_t(1) << (slots.size() - 1));
  Slot &slot = slots[log2Count][b];
  std::call_once(slot.once,
                 [&] { slot.bits = generateBits(hash3(0x706d6a3032, b, 1), log2Count); });
  return slot.bits;
}

// What a seed picks: the base and the two coordinates' scrambling keys.
struct Keys {
  unsigned base;
  std::uint64_t x, y;
};

Keys keysOf(std::uint64_t seed) {
  const std::uint64_t h = mix64(seed ^ 0x3c6ef372fe94f82bull);
  return {static_cast<unsigned>((h >> 32) * kPmj02Bases >> 32), seed ^ 0xa54ff53a5f1d36f1ull,
          seed ^ 0x510e527fade682d1ull};
}

}  // namespace

void checkPmj02Count(std::size_t count) {
  if (count > kPmj02MaxSet)
    throw std::invalid_argument("pmj02: " + std::to_string(count) + " points; at most " +
                                std::to_string(kPmj02MaxSet) + " are served");
}

std::vector<Point2> pmj02Sequence(std::uint64_t seed, int log2Count) {
  const Pmj02Bits s = generateBits(seed, log2Count);
  std::vector<Point2> out(s.x.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = {s.x[i] * 0x1.0p-32, s.y[i] * 0x1.0p-32};
  return out;
}

void pmj02Set(std::uint64_t seed, std::span<Point2> out, DigitRandomization r) {
  const std::size_t n = out.size();
  checkPmj02Count(n);
  if (n == 0) return;
  const int k = log2Ceil(n);
  const Keys keys = keysOf(seed);
  const Pmj02Bits &base = cachedBase(k, r == DigitRandomization::None ? 0 : keys.base);
  const std::span<const std::uint32_t> xs(base.x.data(), n), ys(base.y.data(), n);
  if (r == DigitRandomization::Owen) {
    owenScrambleSet(keys.x, k, xs, out, &Point2::x);
    owenScrambleSet(keys.y, k, ys, out, &Point2::y);
    return;
  }
  const bool shift = r == DigitRandomization::Shift;
  for (std::size_t i = 0; i < n; ++i)
    out[i] = {(shift ? digitalShift(xs[i], keys.x) : xs[i]) * 0x1.0p-32,
              (shift ? digitalShift(ys[i], keys.y) : ys[i]) * 0x1.0p-32};
}

double pmj02Sample(std::uint64_t seed, std::uint64_t index, int coordinate, DigitRandomization r) {
  checkPmj02Count(index + 1);
  const Keys keys = keysOf(seed);
  const Pmj02Bits &base =
      cachedBase(log2Ceil(index + 1), r == DigitRandomization::None ? 0 : keys.base);
  const std::uint32_t bits = coordinate == 0 ? base.x[index] : base.y[index];
  const std::uint64_t key = coordinate == 0 ? keys.x : keys.y;
  switch (r) {
    case DigitRandomization::Owen: return owenScramble(bits, key) * 0x1.0p-32;
    case DigitRandomization::Shift: return digitalShift(bits, key) * 0x1.0p-32;
    case DigitRandomization::None: break;
  }
  return bits * 0x1.0p-32;
}

}  // namespace nuld
