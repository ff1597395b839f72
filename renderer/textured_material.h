#pragma once
// A Disney material whose base colour, metallic and roughness vary over a
// surface by textures, as glTF's metallic-roughness materials do: the
// factors times the texels at the hit's texture coordinates (the colour
// texture's RGB; the metallic-roughness texture's blue and green channels).
// The path tracer makes the Disney BSDF of each hit from it
// (path_integrator.cpp); the lobe tables serve only untextured materials, so
// a textured one is sampled by its own sample() (renderer/README.md).

#include <memory>

#include "materials/disney.h"
#include "renderer/texture.h"

namespace nuld {

struct TexturedDisney {
  DisneyParams factors;
  LobeChoice lobes = kDefaultLobeChoice;
  std::shared_ptr<const Texture> baseColor;          // may be null
  std::shared_ptr<const Texture> metallicRoughness;  // may be null

  // The parameters at `uv`: each product clamped to [0, 1], so that a
  // texel beyond 1 (an HDR texture) still gives a valid material.
  DisneyParams at(Point2 uv) const;
  void hashContent(ContentHash &h) const;
};

}  // namespace nuld
