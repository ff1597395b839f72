// Error against run time (tools/study/equal_time.h) on rows made by hand:
// the ratio and its standard error by hand, the amortized setup, and ties.
#include "tools/study/equal_time.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace nuld::study {
namespace {

TimedRow row(const char *backend, double mse, double stderr_, double seconds, double setup,
             std::size_t spp = 16, double secondsStderr = 0) {
  return {"s", backend, spp, mse, stderr_, seconds, setup, secondsStderr};
}

TEST(EqualTime, RatioIsMseTimesTotalSecondsOverSobols) {
  const std::vector<TimedRow> rows{row("sobol", 2.0, 0.1, 1.0, 0),
                                   row("learned", 1.0, 0.1, 1.5, 10.0),
                                   row("other-spp", 1.0, 0.1, 1.0, 0, 64)};
  const auto k1 = equalTime(rows, 1), k10 = equalTime(rows, 10);
  EXPECT_DOUBLE_EQ(k1[0].ratio, 1);
  EXPECT_DOUBLE_EQ(k1[0].ratioStderr, 0);
  EXPECT_DOUBLE_EQ(k1[1].totalSeconds, 11.5);
  EXPECT_DOUBLE_EQ(k1[1].ratio, 1.0 * 11.5 / 2.0);
  EXPECT_DOUBLE_EQ(k10[1].totalSeconds, 2.5);
  EXPECT_DOUBLE_EQ(k10[1].ratio, 2.5 / 2.0);
  // Relative errors 0.1 and 0.05 add in quadrature.
  EXPECT_NEAR(k10[1].ratioStderr, 1.25 * std::sqrt(0.01 + 0.0025), 1e-12);
  EXPECT_TRUE(std::isnan(k1[2].ratio)) << "no sobol row at 64 spp";
  EXPECT_THROW(equalTime(rows, 0.5), std::invalid_argument);
  EXPECT_THROW(equalTime(rows, NAN), std::invalid_argument);
}

TEST(EqualTime, VerdictSeparatesByTwoStandardErrorsOrCallsATie) {
  // Products: a 1.0, b 1.05 (within 2 SE of a), c 2.0 (beyond).
  const std::vector<TimedRow> rows{row("sobol", 2.0, 0.02, 1.0, 0), row("a", 1.0, 0.03, 1.0, 0),
                                   row("b", 1.05, 0.03, 1.0, 0)};
  const auto v = timeVerdicts(rows, 1);
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].best, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(v[0].runnerUp, "sobol");
  EXPECT_DOUBLE_EQ(v[0].separation, 0.5);
  EXPECT_DOUBLE_EQ(v[0].bestTime.ratio, 0.5);
  EXPECT_NE(describe(v[0]).find("tie between a and b"), std::string::npos) << describe(v[0]);

  // Setup that K = 1 charges in full puts sobol ahead; K = 100 hands it back.
  const std::vector<TimedRow> costly{row("sobol", 2.0, 0.02, 1.0, 0),
                                     row("learned", 1.0, 0.01, 1.0, 50)};
  EXPECT_EQ(timeVerdicts(costly, 1)[0].best[0], "sobol");
  EXPECT_EQ(timeVerdicts(costly, 100)[0].best[0], "learned");
  EXPECT_NE(describe(timeVerdicts(costly, 100)[0]).find("ahead of sobol"), std::string::npos);
}

// The times' error counts: an MSE ratio of 0.8 +- 0.02 at equal median
// times is better at equal time when the times are steady, and a tie when
// their errors (a machine whose load came and went) do not decide the
// products; the relative errors add in quadrature.
TEST(EqualTime, TheTimesErrorJoinsTheMses) {
  const std::vector<TimedRow> steady{row("sobol", 1.0, 0, 1.0, 0, 16, 0.0),
                                     row("a", 0.8, 0.016, 1.0, 0, 16, 0.0)};
  const EqualTime s = equalTime(steady, 1)[1];
  EXPECT_NEAR(s.ratioStderr, 0.8 * 0.02, 1e-12);
  EXPECT_EQ(verdictOf(s.ratio, s.ratioStderr), Verdict::Better);

  const std::vector<TimedRow> noisy{row("sobol", 1.0, 0, 1.0, 0, 16, 0.1),
                                    row("a", 0.8, 0.016, 1.0, 0, 16, 0.1)};
  const EqualTime n = equalTime(noisy, 1)[1];
  EXPECT_NEAR(n.ratioStderr, 0.8 * std::sqrt(0.02 * 0.02 + 0.1 * 0.1 + 0.1 * 0.1), 1e-12);
  EXPECT_EQ(verdictOf(n.ratio, n.ratioStderr), Verdict::Tie);
  // The verdicts between rows see it too: a and sobol tie.
  EXPECT_EQ(timeVerdicts(noisy, 1)[0].best, (std::vector<std::string>{"a", "sobol"}));
  // Setup is exact: a time error is relative to the whole total.
  const std::vector<TimedRow> setup{row("sobol", 1.0, 0, 1.0, 0, 16, 0.0),
                                    row("a", 1.0, 0, 1.0, 9.0, 16, 0.1)};
  EXPECT_NEAR(equalTime(setup, 1)[1].ratioStderr, 10.0 * 0.1 / 10.0, 1e-12);
}

}  // namespace
}  // namespace nuld::study
