#pragma once
// The built-in scene `veach-mis`: Veach's multiple importance sampling test
// (his thesis, figure 9.2) as Mitsuba 0.5's veach_mi scene sets it up
// (scenes/README.md has the numbers): four metal plates of increasing
// roughness, each reflecting four spherical lights of equal power and
// radii from 0.9 down to 0.0333, and a fifth sphere lighting the scene,
// seen from (0, 6, 27.5), 768 x 512. It needs no files and no environment
// map; the plates are Disney metals, so a backend that samples lobes
// tabulates them.

#include "scenes/scene_file.h"

namespace nuld {

LoadedScene makeVeachMisScene(LobeChoice lobes);

}  // namespace nuld
