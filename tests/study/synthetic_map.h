#pragma once
// The integration study tests' synthetic environment map.

#include <vector>

#include "sampler/io/image_io.h"

namespace nuld::study::test {

// A 16 x 8 map: a smooth sky, a black band (zero density) and one hot pixel,
// so the references see discontinuities, zero cells and a peak.
inline Image syntheticMap() {
  Image m{16, 8, 3, std::vector<float>(16 * 8 * 3)};
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 16; ++i)
      for (int c = 0; c < 3; ++c)
        m.at(i, j, c) = j == 5 ? 0.0f : float(0.2 + 0.1 * j + 0.05 * i + 0.1 * c);
  for (int c = 0; c < 3; ++c) m.at(5, 2, c) = 40.0f;
  return m;
}

}  // namespace nuld::study::test
