// The estimators of the integration study: one importance-sampling estimate
// per point set, and the statistics over a sampler's instances.

#include <cmath>
#include <stdexcept>
#include <vector>

#include "tools/study/integration_study.h"
#include "tools/study/statistics.h"

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
  if (e.size() < 2) throw std::invalid_argument("summarize: need at least 2 estimates");
  const MeanAndError estimates = meanAndError(e);
  // The MSE is itself a mean over the instances: its standard error decides
  // whether two samplers' MSEs differ (heavy-tailed on HDR integrands).
  std::vector<double> squaredErrors;
  for (double v : e) squaredErrors.push_back((v - reference) * (v - reference));
  const MeanAndError mse = meanAndError(squaredErrors);
  EstimateStats s;
  s.mean = estimates.mean;
  s.std = estimates.std;
  s.bias = s.mean - reference;
  s.biasStderr = estimates.stderr_;
  s.rmse = std::sqrt(mse.mean);
  s.mseStderr = mse.stderr_;
  s.relRmse = reference != 0 ? s.rmse / std::abs(reference) : NAN;
  return s;
}

}  // namespace nuld::study
