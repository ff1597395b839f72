#pragma once
// A pinhole perspective camera set up like pbrt's LookAt + "perspective":
// `fov` is the full angle of the image's shorter side. Image right is
// cross(view, up), as in a right-handed world. pbrt's LookAt is left-handed
// (right = cross(up, view)); pbrt scenes that write `Scale -1 1 1` before
// LookAt undo that and match this camera as is, while a bare pbrt LookAt
// matches it with `mirrorX`.

#include "materials/vec3.h"
#include "renderer/embree_scene.h"
#include "sampler/point.h"

namespace nuld {

struct CameraSettings {
  Vec3 eye{0, 0, 5}, target{0, 0, 0}, up{0, 1, 0};
  double fovDegrees = 40;
  bool mirrorX = false;
};

class PerspectiveCamera {
 public:
  PerspectiveCamera(const CameraSettings &settings, int width, int height);

  // A ray through film position (x, y) in pixels; (0, 0) is the top-left
  // corner of the image, (width, height) the bottom-right one.
  Ray generateRay(Point2 film) const;

 private:
  Vec3 eye_, right_, up_, forward_;
  double halfWidth_, halfHeight_;  // image plane extent at distance 1
  int width_, height_;
};

}  // namespace nuld
