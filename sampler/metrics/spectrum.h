#pragma once
// Fourier power spectrum of a 2D point set, P(k) = |sum_j exp(-2 pi i k.x_j)|^2 / N
// for integer frequencies k in [-K, K]^2, and its radial average.

#include <span>
#include <vector>

#include "sampler/point.h"

namespace nuld {

struct PowerSpectrum {
  int halfSize = 0;            // K
  std::vector<double> power;   // (2K+1)^2, row-major, k = (i - K, j - K); DC included
  std::vector<double> radial;  // mean power in rings |k| in [r - 1/2, r + 1/2), r = 0..K
  double at(int kx, int ky) const {
    return power[std::size_t(ky + halfSize) * (2 * halfSize + 1) + kx + halfSize];
  }
};

PowerSpectrum powerSpectrum(std::span<const Point2> points, int halfSize);

// Average of the spectra of several instances (the usual way to read them).
PowerSpectrum averagePowerSpectrum(const PointSet &set, int halfSize);

}  // namespace nuld
