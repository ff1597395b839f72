#include "scenes/material_factory.h"

#include <stdexcept>

#include "materials/disney.h"
#include "materials/lambertian.h"

namespace nuld {

std::shared_ptr<const Bsdf> makeMaterial(const JsonReader &m, LobeChoice lobes) {
  const std::string type = m["type"].string();
  if (type == "lambertian") {
    m.allowOnly({"type", "albedo"});
    return std::make_shared<Lambertian>(m.has("albedo") ? m["albedo"].reflectance()
                                                        : Rgb::grey(0.5));
  }
  if (type != "disney") m["type"].fail("\"disney\" or \"lambertian\"");
  m.allowOnly({"type", "base_color", "metallic", "subsurface", "specular", "roughness",
               "specular_tint", "anisotropic", "sheen", "sheen_tint", "clearcoat",
               "clearcoat_gloss", "spec_trans", "ior"});
  DisneyParams p;
  if (m.has("base_color")) p.baseColor = m["base_color"].reflectance();
  const auto unit = [&](const char *key, double &value) { value = m.number(key, value, 0, 1); };
  unit("metallic", p.metallic);
  unit("subsurface", p.subsurface);
  unit("specular", p.specular);
  unit("roughness", p.roughness);
  unit("specular_tint", p.specularTint);
  unit("anisotropic", p.anisotropic);
  unit("sheen", p.sheen);
  unit("sheen_tint", p.sheenTint);
  unit("clearcoat", p.clearcoat);
  unit("clearcoat_gloss", p.clearcoatGloss);
  unit("spec_trans", p.specTrans);
  // The model refuses 1 itself (no interface), with its reason.
  p.ior = m.number("ior", p.ior, 1, 4);
  // The checks above are the model's own; any it adds later still names the field.
  try {
    return std::make_shared<DisneyBrdf>(p, lobes);
  } catch (const std::invalid_argument &e) {
    m.refuse(e.what());
  }
}

}  // namespace nuld
