// The integration study's estimators (tools/study/integrate_estimators.h):
// a point of zero density counts 0, never NaN, and the summary's RMSE, bias
// and standard deviation satisfy rmse^2 = bias^2 + (K - 1) / K std^2.
#include "tools/study/integrate_estimators.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tools/study/integrands.h"

namespace nuld::study {
namespace {

TEST(IntegrationStudyEstimator, ZeroPdfPointsAreCountedNotNan) {
  const Integrand in = makeQuarterDiscBilinear();
  const std::vector<Point2> pts{{0.1, 0.1}, {0.95, 0.95}, {NAN, 0.2}, {0.2, 0.3}};
  std::size_t zero = 0;
  const double e = importanceEstimate(in, pts, zero);
  EXPECT_EQ(zero, 2u);
  EXPECT_TRUE(std::isfinite(e));
}

TEST(IntegrationStudyEstimator, SummaryIdentity) {
  const std::vector<double> e{1.0, 1.2, 0.9, 1.4};
  const EstimateStats s = summarize(e, 1.05);
  const double K = 4;
  EXPECT_NEAR(s.rmse * s.rmse, s.bias * s.bias + (K - 1) / K * s.std * s.std, 1e-14);
  EXPECT_NEAR(s.biasStderr, s.std / 2, 1e-15);
  // Squared errors .0025 .0225 .0225 .1225: mean .0425, sample variance
  // (.0016 + .0004 + .0004 + .0064) / 3, so the MSE's standard error is
  // sqrt(.0088 / 3 / 4).
  EXPECT_NEAR(s.mseStderr, std::sqrt(0.0088 / 12), 1e-12);
  EXPECT_THROW(summarize(std::vector<double>{1.0}, 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace nuld::study
