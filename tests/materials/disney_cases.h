#pragma once
// Disney parameter sets shared by the materials tests.

#include "materials/disney.h"

namespace nuld::test {

// Every parameter away from zero (and from one), so no lobe or term is skipped.
inline DisneyParams allParametersNonZero(double roughness) {
  DisneyParams p;
  p.baseColor = {0.2, 0.5, 0.8};
  p.metallic = 0.3;
  p.subsurface = 0.4;
  p.specular = 0.7;
  p.roughness = roughness;
  p.specularTint = 0.5;
  p.anisotropic = 0.6;
  p.sheen = 1;
  p.sheenTint = 0.5;
  p.clearcoat = 0.5;
  p.clearcoatGloss = 0.3;
  return p;
}

}  // namespace nuld::test
