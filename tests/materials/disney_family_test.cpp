// The `family:disney` target family: gamma = (theta / 89 degrees, phi / 360 degrees) of wo.

#include <gtest/gtest.h>

#include "materials/disney_target.h"
#include "sampler/targets/target_family.h"
#include "sampler/targets/target_spec.h"

namespace nuld {
namespace {

TEST(DisneyFamily, GammaSelectsTheViewDirection) {
  registerMaterialTargets();
  const auto family = makeTargetFamily("family:disney:res=32");
  EXPECT_EQ(family->gammaDimension(), 2u);
  EXPECT_EQ(family->domain(), Domain::Hemisphere);
  EXPECT_EQ(makeTargetFamily(family->spec())->spec(), family->spec());
  const auto a = family->target(std::vector<double>{45.0 / 89, 0});
  const auto b = makeTarget("disney:theta=45,res=32");
  // The same table as the plain spec with that view.
  for (double u = 0.05; u < 1; u += 0.1)
    for (double v = 0.02; v < 0.5; v += 0.05) EXPECT_DOUBLE_EQ(a->pdf({u, v}), b->pdf({u, v}));
  // Grazing (gamma 1 = 89 degrees) is still a proper density.
  const auto grazing = family->target(std::vector<double>{1, 0.3});
  EXPECT_NEAR(grazing->mass({{0, 0}, {1, 1}}), 1, 1e-12);
  EXPECT_THROW(makeTargetFamily("family:disney:theta=30"), std::invalid_argument);
  EXPECT_THROW(family->target(std::vector<double>{0.5}), std::invalid_argument);
}

}  // namespace
}  // namespace nuld
