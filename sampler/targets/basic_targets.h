#pragma once
// Targets with closed-form density, mass and inverse: uniform, bilinear,
// truncated Gaussian, quarter-disc and step.

#include <array>

#include "sampler/targets/target.h"

namespace nuld {

class UniformTarget final : public Target {
 public:
  explicit UniformTarget(Domain d = Domain::Square) : domain_(d) {}
  std::string spec() const override { return "uniform"; }
  Domain domain() const override { return domain_; }
  bool isUniform() const override { return true; }
  double pdf(Point2 p) const override;
  double mass(const Box2 &b) const override { return b.clipped().area(); }
  Inversion invert(Point2 u) const override { return {u, {}}; }

 private:
  Domain domain_;
};

// Density proportional to the bilinear interpolation of the corner weights
// w00 (at (0,0)), w10 (1,0), w01 (0,1), w11 (1,1); weights >= 0, not all 0.
// Only their ratios matter: they are divided by the largest, which must be a
// normal double (>= 2.2e-308); smaller ones underflow and are refused.
class BilinearTarget final : public Target {
 public:
  BilinearTarget(double w00, double w10, double w01, double w11);
  std::string spec() const override;
  double pdf(Point2 p) const override;
  double mass(const Box2 &b) const override;
  Inversion invert(Point2 u) const override;

 private:
  std::array<double, 4> spec_;  // the weights as given (the spec)
  std::array<double, 4> w_;     // w00, w10, w01, w11, over the largest when far from 1
  double norm_;                 // integral of the density w_ describes
};

// An isotropic Gaussian (mean (mx, my), standard deviation sigma) truncated
// to the unit square. sigma >= kMinSigma: narrower, the points are the mean
// to double precision and the density overflows.
class GaussianTarget final : public Target {
 public:
  static constexpr double kMinSigma = 1e-12;
  GaussianTarget(double mx, double my, double sigma);
  std::string spec() const override;
  double pdf(Point2 p) const override;
  double mass(const Box2 &b) const override;
  Inversion invert(Point2 u) const override;

 private:
  struct Axis {
    double mean, sigma;
    double massBelow(double x) const;  // unnormalized, stable in both tails
    double total;                      // mass inside [0, 1]
    double pdf(double x) const;        // normalized on [0, 1]
    double inverse(double u) const;
  };
  Axis ax_, ay_;
};

// Uniform on the quarter disc x^2 + y^2 <= 1 inside the unit square.
class QuarterDiscTarget final : public Target {
 public:
  std::string spec() const override { return "quarterdisc"; }
  double pdf(Point2 p) const override;
  double mass(const Box2 &b) const override;
  Inversion invert(Point2 u) const override;
};

// Density proportional to `left` for x < x0 and to `right` for x >= x0.
class StepTarget final : public Target {
 public:
  StepTarget(double x0, double left, double right);
  std::string spec() const override;
  double pdf(Point2 p) const override;
  double mass(const Box2 &b) const override;
  Inversion invert(Point2 u) const override;

 private:
  double massBelow(double x) const;
  double x0_, left_, right_, norm_;
};

}  // namespace nuld
