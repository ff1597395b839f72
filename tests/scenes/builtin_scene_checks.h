#pragma once
// A check the built-in area-lit scenes share: every classic word under every
// integrator renders a small image without a rejected sample, every value
// finite and their sum positive.
#include <gtest/gtest.h>

#include <cmath>

#include "backends/backend_registry.h"
#include "renderer/render.h"
#include "scenes/scene_file.h"

namespace nuld::test {

// `base`: the scene's settings with the image's size (and depth) set.
inline void expectFiniteRendersWithEveryClassicWord(const LoadedScene &s,
                                                    const RenderSettings &base) {
  for (const char *word : {"independent", "stratified", "sobol", "halton", "pmj02", "zsobol",
                           "sobol-full", "lattice", "lattice-baker", "sobol-tabulated"})
    for (IntegratorKind kind : {IntegratorKind::Path, IntegratorKind::Direct, IntegratorKind::Light,
                                IntegratorKind::Bsdf}) {
      RenderSettings settings = base;
      settings.spp = 4;
      settings.integrator = kind;
      auto backend = makeBackend(word, 3);
      RenderStats stats;
      const Image img = render(s.scene, settings, *backend, &stats);
      EXPECT_EQ(stats.rejectedSamples, 0u) << s.name << " " << word;
      double sum = 0;
      for (float v : img.pixels) {
        ASSERT_TRUE(std::isfinite(v)) << s.name << " " << word << " " << toString(kind);
        sum += v;
      }
      EXPECT_GT(sum, 0) << s.name << " " << word << " " << toString(kind);
    }
}

}  // namespace nuld::test
