#pragma once
// The one summary of repeated measurements that both studies report: the
// mean, the sample standard deviation (n - 1) and the standard error of the
// mean (the deviation over sqrt n); and the one ratio of two such means that
// the render study reports (to sobol, to the best classic backend, at equal
// time).

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

namespace nuld::study {

struct MeanAndError {
  double mean = 0, std = 0, stderr_ = 0;
};

// Zero deviation and error for fewer than two values.
inline MeanAndError meanAndError(std::span<const double> v) {
  MeanAndError s;
  const double n = double(v.size());
  for (double x : v) s.mean += x / n;
  if (v.size() > 1) {
    double ss = 0;
    for (double x : v) ss += (x - s.mean) * (x - s.mean);
    s.std = std::sqrt(ss / (n - 1));
    s.stderr_ = std::sqrt(ss / (n - 1) / n);
  }
  return s;
}

// Render times: the median (a repeat slowed by other work on the machine
// moves it less than the mean), the median absolute deviation (the spread
// printed beside it) and the median's standard error, 1.2533 s / sqrt n as
// for a normal sample but with s the sample standard deviation rather than
// one estimated from the MAD: load that comes and goes leaves the times in
// two clusters, whose median may fall in either while their MAD stays
// small, and s sees both. Zero spread and error for fewer than two values.
struct MedianAndSpread {
  double median = 0, mad = 0, stderr_ = 0;
};
inline double medianOf(std::vector<double> v) {
  if (v.empty()) return NAN;
  const std::size_t h = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(h), v.end());
  const double upper = v[h];
  if (v.size() % 2) return upper;
  return 0.5 * (upper + *std::max_element(v.begin(), v.begin() + std::ptrdiff_t(h)));
}
inline MedianAndSpread medianAndSpread(std::span<const double> v) {
  MedianAndSpread s;
  if (v.empty()) return s;
  s.median = medianOf({v.begin(), v.end()});
  if (v.size() < 2) return s;
  std::vector<double> deviation;
  for (double x : v) deviation.push_back(std::abs(x - s.median));
  s.mad = medianOf(std::move(deviation));
  s.stderr_ = 1.2533 * meanAndError(v).stderr_;
  return s;
}

// a / b of two independent means with the ratio's standard error to first
// order: q sqrt((ea / a)^2 + (eb / b)^2). A relative error that is not a
// number (a mean of 0, an error of one repeat) counts as 0. NaN when b is
// not positive.
struct Ratio {
  double value = NAN, stderr_ = NAN;
};
// e / m, or 0 where that is not a number or m is not positive.
inline double relativeError(double e, double m) {
  const double r = e / m;
  return m > 0 && std::isfinite(r) ? r : 0.0;
}
inline Ratio ratioOfMeans(double a, double aStderr, double b, double bStderr) {
  if (!(b > 0)) return {};
  const double q = a / b, ra = relativeError(aStderr, a), rb = relativeError(bStderr, b);
  return {q, q * std::sqrt(ra * ra + rb * rb)};
}

// A ratio against 1: better or worse by more than two standard errors, else
// a tie; undecided when its error is not positive (a single repeat's error
// is 0, which says nothing of the noise).
enum class Verdict { Better, Tie, Worse, Undecided };
inline Verdict verdictOf(double q, double se) {
  if (!(se > 0) || !std::isfinite(q)) return Verdict::Undecided;
  return q + 2 * se < 1 ? Verdict::Better : q - 2 * se > 1 ? Verdict::Worse : Verdict::Tie;
}
inline const char *verdictName(Verdict v) {
  constexpr const char *names[] = {"better", "tie", "worse", "n/a"};
  return names[int(v)];
}

// A render cell's repeats split into render time and one-time setup: each
// repeat's `whole` seconds include `made`, the seconds its backend spent
// making sets as it prepared (RenderStats::setsMadeSeconds: a neural
// model's banks, made in the first repeat and found by the others), which
// are the cell's setup, not its render time.
struct RepeatSeconds {
  std::vector<double> render;
  double setup = 0;
};
inline RepeatSeconds splitRepeatSeconds(std::span<const double> whole,
                                        std::span<const double> made) {
  RepeatSeconds out;
  for (std::size_t r = 0; r < whole.size(); ++r) {
    const double m = r < made.size() ? made[r] : 0.0;
    out.render.push_back(whole[r] - m);
    out.setup += m;
  }
  return out;
}

}  // namespace nuld::study
