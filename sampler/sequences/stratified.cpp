#include "sampler/sequences/stratified.h"

#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "sampler/sequences/rng.h"

namespace nuld {

std::uint32_t stratifiedGridSide(std::size_t n) {
  if (n > (std::size_t(1) << 40)) throw std::invalid_argument("stratified: too many points");
  auto m = static_cast<std::uint64_t>(std::sqrt(double(n)));
  while (m * m < n) ++m;  // the square root may round either way
  while (m > 0 && (m - 1) * (m - 1) >= n) --m;
  return static_cast<std::uint32_t>(m);
}

void stratifiedSet(std::uint64_t seed, std::span<Point2> out) {
  const std::size_t n = out.size();
  if (n == 0) return;
  const std::uint32_t m = stratifiedGridSide(n);
  const std::size_t cells = std::size_t(m) * m;
  if (cells > 0xffffffffull) throw std::invalid_argument("stratified: too many points");
  // The cells by index, shuffled in front as they are drawn: on the stack
  // up to 1024 cells (the renderer's sets), in a per-thread buffer beyond.
  std::array<std::uint32_t, 1024> small;
  thread_local std::vector<std::uint32_t> large;
  if (cells > small.size()) large.resize(cells);
  std::uint32_t *const cell = cells > small.size() ? large.data() : small.data();
  for (std::uint32_t c = 0; c < cells; ++c) cell[c] = c;
  Rng rng(seed, 0x57a7);
  for (std::size_t i = 0; i < n; ++i) {
    // A partial Fisher-Yates shuffle: cell[i] is drawn uniformly from the
    // cells not drawn yet, so cell[0..n) is a uniformly random ordered
    // sample without replacement (all of them, shuffled, for a square N).
    const std::size_t j = i + rng.uniformInt(std::uint32_t(cells - i));
    std::swap(cell[i], cell[j]);
    // One 64-bit draw for both coordinates' jitter: 32 bits each.
    const std::uint64_t bits = rng.nextBits();
    const double jx = double(bits >> 32) * 0x1.0p-32, jy = double(bits & 0xffffffffu) * 0x1.0p-32;
    // Divided, not multiplied by 1 / m: a correctly rounded quotient of
    // values below m stays below 1.
    out[i] = {(cell[i] % m + jx) / m, (cell[i] / m + jy) / m};
  }
}

}  // namespace nuld
