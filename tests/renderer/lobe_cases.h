#pragma once
// The Disney materials and table settings the lobe-table tests share
// (lobe_routes_test.cpp, tests/backends/set_plans_test.cpp).

#include <memory>

#include "materials/disney.h"
#include "renderer/lobe_tables.h"

namespace nuld::test {

inline std::shared_ptr<const DisneyBrdf> material(double roughness, double anisotropic,
                                                  double metallic,
                                                  LobeChoice choice = kDefaultLobeChoice) {
  DisneyParams p;
  p.roughness = roughness;
  p.anisotropic = anisotropic;
  p.metallic = metallic;
  p.baseColor = {0.9, 0.8, 0.6};
  return std::make_shared<DisneyBrdf>(p, choice);
}

// Every bin served by its table, with a defensive share: the worst case for
// weights (no bin handed back to the material's sampler).
inline LobeTableSettings everyBin(double defensive, int cells = 64) {
  return {9, 3, cells, 1.0, LobeRouting::Table, defensive};
}

}  // namespace nuld::test
