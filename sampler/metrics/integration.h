#pragma once
// Integration error of a point set used as importance samples of a target:
// the estimate (1/N) sum f(x_i) / p(x_i) against a known integral.

#include <functional>
#include <span>
#include <string>

#include "sampler/point.h"
#include "sampler/targets/target.h"

namespace nuld {

struct TestIntegrand {
  std::string name;
  std::function<double(Point2)> f;
  double integral;  // over the unit square, exact
};

// Test integrands with closed-form integrals: "step" (1 for x < 0.5),
// "disc" (the indicator of the quarter disc), "bilinear" (x y), "gaussian"
// (exp(-|x - c|^2 / (2 * 0.15^2)), c = (0.4, 0.6), untruncated over the square).
TestIntegrand makeTestIntegrand(const std::string &name);

// Importance-sampling estimate of the integral of f; points where the target
// density is zero contribute nothing (they should not occur).
double estimateIntegral(std::span<const Point2> points, const Target &target,
                        const std::function<double(Point2)> &f);

}  // namespace nuld
