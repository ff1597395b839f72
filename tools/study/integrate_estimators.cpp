// The estimators of the integration study: one importance-sampling estimate
// per point set, and the statistics over a sampler's instances.

#include <cmath>
#include <stdexcept>

#include "tools/study/integration_study.h"

namespace nuld::study {

double importanceEstimate(const Integrand &in, std::span<const Point2> points,
                          std::size_t &zeroPdf) {
  double sum = 0;
  for (const Point2 &x : points) {
    const double p = isFinite(x) ? in.target->pdf(x) : 0.0;
    const double v = p > 0 ? in.f(x) / p : 0.0;
    if (!(p > 0) || !std::isfinite(v)) {
      ++zeroPdf;
      continue;
    }
    sum += v;
  }
  return points.empty() ? 0.0 : sum / double(points.size());
}

EstimateStats summarize(std::span<const double> e, double reference) {
  const double K = double(e.size());
  if (e.size() < 2) throw std::invalid_argument("summarize: need at least 2 estimates");
  EstimateStats s;
  for (double v : e) s.mean += v / K;
  double var = 0, mse = 0;
  for (double v : e) {
    var += (v - s.mean) * (v - s.mean);
    mse += (v - reference) * (v - reference);
  }
  s.std = std::sqrt(var / (K - 1));
  s.bias = s.mean - reference;
  s.biasStderr = s.std / std::sqrt(K);
  s.rmse = std::sqrt(mse / K);
  // The MSE is itself a mean over the instances: its standard error decides
  // whether two samplers' MSEs differ (heavy-tailed on HDR integrands).
  double sqVar = 0;
  for (double v : e) {
    const double d = (v - reference) * (v - reference) - mse / K;
    sqVar += d * d;
  }
  s.mseStderr = std::sqrt(sqVar / (K - 1) / K);
  s.relRmse = reference != 0 ? s.rmse / std::abs(reference) : NAN;
  return s;
}

}  // namespace nuld::study
