#include "sampler/metrics/spectrum.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>

namespace nuld {

PowerSpectrum powerSpectrum(std::span<const Point2> points, int K) {
  if (K < 1) throw std::invalid_argument("power spectrum: half size must be >= 1");
  if (points.empty()) throw std::invalid_argument("power spectrum: empty point set");
  const int S = 2 * K + 1;
  PowerSpectrum ps;
  ps.halfSize = K;
  ps.power.assign(std::size_t(S) * S, 0.0);
  // Row ky: sum over points of e^{-2 pi i ky y} e^{-2 pi i kx x}, the x factors
  // built by repeated multiplication from e^{-2 pi i x}.
  tbb::parallel_for(0, S, [&](int row) {
    const int ky = row - K;
    std::vector<std::complex<double>> acc(S, 0.0);
    for (const Point2 &p : points) {
      const double ty = -2 * std::numbers::pi * ky * p.y;
      const std::complex<double> fy(std::cos(ty), std::sin(ty));
      const double tx = -2 * std::numbers::pi * p.x;
      const std::complex<double> step(std::cos(tx), std::sin(tx));
      std::complex<double> f = fy * std::polar(1.0, 2 * std::numbers::pi * K * p.x);  // kx = -K
      for (int i = 0; i < S; ++i) {
        acc[i] += f;
        f *= step;
      }
    }
    for (int i = 0; i < S; ++i)
      ps.power[std::size_t(row) * S + i] = std::norm(acc[i]) / double(points.size());
  });
  ps.radial.assign(K + 1, 0.0);
  std::vector<int> hits(K + 1, 0);
  for (int j = -K; j <= K; ++j)
    for (int i = -K; i <= K; ++i) {
      const int r = int(std::lround(std::sqrt(double(i * i + j * j))));
      if (r <= K) {
        ps.radial[r] += ps.at(i, j);
        ++hits[r];
      }
    }
  for (int r = 0; r <= K; ++r) ps.radial[r] /= std::max(hits[r], 1);
  return ps;
}

PowerSpectrum averagePowerSpectrum(const PointSet &set, int K) {
  if (set.instances() == 0) throw std::invalid_argument("power spectrum: empty point set");
  PowerSpectrum sum;
  for (std::size_t k = 0; k < set.instances(); ++k) {
    PowerSpectrum one = powerSpectrum(set.instance(k), K);
    if (k == 0) {
      sum = std::move(one);
      continue;
    }
    for (std::size_t i = 0; i < sum.power.size(); ++i) sum.power[i] += one.power[i];
    for (std::size_t i = 0; i < sum.radial.size(); ++i) sum.radial[i] += one.radial[i];
  }
  const double inv = 1.0 / double(std::max<std::size_t>(1, set.instances()));
  for (double &v : sum.power) v *= inv;
  for (double &v : sum.radial) v *= inv;
  return sum;
}

}  // namespace nuld
