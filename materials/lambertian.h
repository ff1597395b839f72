#pragma once
// The ideal diffuse reflector: f = albedo / pi, sampled cosine-weighted.

#include "materials/bsdf.h"

namespace nuld {

class Lambertian final : public Bsdf {
 public:
  explicit Lambertian(Rgb albedo) : albedo_(albedo) {}

  Rgb albedo() const { return albedo_; }

  std::string name() const override { return "lambertian"; }
  void hashContent(ContentHash &h) const override {
    h.add(name()).add(albedo_.r).add(albedo_.g).add(albedo_.b);
  }
  Rgb eval(Vec3 wo, Vec3 wi) const override;
  double pdf(Vec3 wo, Vec3 wi) const override;
  std::optional<BsdfSample> sample(Vec3 wo, double uc, Point2 u) const override;

 private:
  Rgb albedo_;
};

}  // namespace nuld
