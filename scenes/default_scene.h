#pragma once
// The built-in scene `default`: three spheres (glossy Disney, rough metal and
// a subsurface-tinted diffuse) on a grey floor under a procedural sky with a
// small bright sun. It needs no files, so `nuld render default` works
// anywhere, and the sun makes environment-map importance sampling matter.

#include "renderer/shapes.h"
#include "scenes/scene_file.h"

namespace nuld {

// Its Disney materials pick their lobes by `choices.lobes`
// (materials/disney.h); its sky's importance is `choices.importance`, else
// kDefaultImportance.
LoadedScene makeDefaultScene(const SceneChoices &choices = {});

// The built-in scene `stress`, for stability studies: the default layout with
// roughness 0 (a metal mirror, an anisotropic dielectric with clearcoat),
// roughness 1 (subsurface, sheen), a glossy floor seen from 2 cm above it
// (grazing views) and a sun 1e6 times brighter than the sky.
LoadedScene makeStressScene(const SceneChoices &choices = {});

// The procedural sky: a lat-long map (row 0 = zenith) with a blue gradient, a
// darker ground and a sun disc of `sunRadiance` (so the dynamic range can be
// made extreme for stability tests).
Image proceduralSky(int width, int height, double sunRadiance = 2000.0);

}  // namespace nuld
