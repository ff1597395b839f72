#include "renderer/textured_material.h"

#include <algorithm>

namespace nuld {

DisneyParams TexturedDisney::at(Point2 uv) const {
  DisneyParams p = factors;
  const auto unit = [](double v) { return std::clamp(v, 0.0, 1.0); };
  if (baseColor) {
    const Rgb t = baseColor->lookup(uv);
    p.baseColor = {unit(p.baseColor.r * t.r), unit(p.baseColor.g * t.g), unit(p.baseColor.b * t.b)};
  }
  if (metallicRoughness) {
    const Rgb t = metallicRoughness->lookup(uv);
    p.roughness = unit(p.roughness * t.g);
    p.metallic = unit(p.metallic * t.b);
  }
  return p;
}

void TexturedDisney::hashContent(ContentHash &h) const {
  h.add("textured-disney");
  DisneyBrdf(factors, lobes).hashContent(h);
  h.add(std::uint64_t(bool(baseColor))).add(std::uint64_t(bool(metallicRoughness)));
  if (baseColor) baseColor->hashContent(h);
  if (metallicRoughness) metallicRoughness->hashContent(h);
}

}  // namespace nuld
