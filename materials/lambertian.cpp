#include "materials/lambertian.h"

#include "materials/sampling.h"

namespace nuld {

Rgb Lambertian::eval(Vec3 wo, Vec3 wi) const {
  if (!(wo.z > 0) || !(wi.z > 0)) return {};
  return albedo_ * kInvPi;
}

double Lambertian::pdf(Vec3 wo, Vec3 wi) const {
  if (!(wo.z > 0)) return 0;
  return cosineHemispherePdf(wi.z);
}

std::optional<BsdfSample> Lambertian::sample(Vec3 wo, double, Point2 u) const {
  if (!(wo.z > 0)) return std::nullopt;
  const Vec3 wi = cosineHemisphere(u);
  if (!(wi.z > 0)) return std::nullopt;  // only for u.x = 1, outside [0,1)
  const double pdf = cosineHemispherePdf(wi.z);
  return BsdfSample{wi, albedo_ * kInvPi, pdf, pdf};
}

}  // namespace nuld
