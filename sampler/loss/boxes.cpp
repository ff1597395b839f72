#include "sampler/loss/boxes.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>

namespace nuld {

Box2 sampleBox(BoxKind kind, Rng &rng) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  switch (kind) {
    case BoxKind::MultipleCorner: {
      const std::uint64_t corner = rng.nextBits() >> 62;
      const Point2 y{rng.uniform(), rng.uniform()};
      Box2 b;
      for (int k = 0; k < 2; ++k) {
        const bool high = (corner >> k) & 1;
        b.lo[k] = high ? y[k] : -inf;
        b.hi[k] = high ? inf : y[k];
      }
      return b;
    }
    case BoxKind::Anchored: {
      const Point2 y{rng.uniform(), rng.uniform()};
      return {{-inf, -inf}, y};
    }
    case BoxKind::TwoPoint: {
      const Point2 a{rng.uniform(), rng.uniform()}, c{rng.uniform(), rng.uniform()};
      return {{std::min(a.x, c.x), std::min(a.y, c.y)}, {std::max(a.x, c.x), std::max(a.y, c.y)}};
    }
  }
  return {};
}

int drawsPerBox(BoxKind kind) {
  switch (kind) {
    case BoxKind::MultipleCorner: return 3;
    case BoxKind::Anchored: return 2;
    case BoxKind::TwoPoint: return 4;
  }
  return 0;
}

void sampleBoxes(BoxKind kind, Rng &rng, std::span<Box2> out) {
  const std::uint64_t draws = std::uint64_t(drawsPerBox(kind));
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, out.size(), 2048), [&](const auto &r) {
    Rng local = rng;
    local.advance(draws * r.begin());
    for (std::size_t m = r.begin(); m < r.end(); ++m) out[m] = sampleBox(kind, local);
  });
  rng.advance(draws * out.size());
}

}  // namespace nuld
