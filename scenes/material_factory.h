#pragma once
// Materials from their JSON description:
//   {"type": "disney", "base_color": [r,g,b], "metallic": 0, "subsurface": 0,
//    "specular": 0.5, "roughness": 0.5, "specular_tint": 0, "anisotropic": 0,
//    "sheen": 0, "sheen_tint": 0, "clearcoat": 0, "clearcoat_gloss": 1}
//   {"type": "lambertian", "albedo": [r,g,b]}
// Omitted Disney parameters take the defaults of DisneyParams; every scalar,
// and every channel of a colour (a reflectance), must lie in [0, 1].

#include <memory>

#include "materials/bsdf.h"
#include "materials/disney.h"
#include "scenes/json_reader.h"

namespace nuld {

// A Disney material samples its lobes by `lobes` (materials/disney.h).
std::shared_ptr<const Bsdf> makeMaterial(const JsonReader &description, LobeChoice lobes);

}  // namespace nuld
