#include "renderer/camera.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace nuld {

PerspectiveCamera::PerspectiveCamera(const CameraSettings &s, int width, int height)
    : eye_(s.eye), width_(width), height_(height) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("camera: film size must be positive");
  if (!(s.fovDegrees > 0 && s.fovDegrees < 180))
    throw std::invalid_argument("camera: fov must be in (0, 180) degrees");
  const Vec3 view = s.target - s.eye;
  if (!(length(view) > 0)) throw std::invalid_argument("camera: eye and target coincide");
  forward_ = normalize(view);
  const Vec3 side = cross(forward_, s.up);
  if (!(length(side) > 1e-12)) throw std::invalid_argument("camera: up is parallel to the view");
  right_ = normalize(side);
  up_ = cross(right_, forward_);
  if (s.mirrorX) right_ = -right_;
  const double tanHalf = std::tan(0.5 * s.fovDegrees * std::numbers::pi / 180);
  const double aspect = double(width) / height;
  // pbrt: the field of view spans the shorter image side.
  halfWidth_ = aspect >= 1 ? tanHalf * aspect : tanHalf;
  halfHeight_ = aspect >= 1 ? tanHalf : tanHalf / aspect;
}

Ray PerspectiveCamera::generateRay(Point2 film) const {
  const double sx = (2 * film.x / width_ - 1) * halfWidth_;
  const double sy = (1 - 2 * film.y / height_) * halfHeight_;
  return {eye_, normalize(forward_ + sx * right_ + sy * up_)};
}

}  // namespace nuld
