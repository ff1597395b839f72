#pragma once
// The built-in scene `cornell`: the Cornell box as Mitsuba 3 builds it
// (mitsuba.cornell_box(), scenes/README.md has the numbers): a box of
// [-1, 1]^3 with white floor, ceiling and back wall, a red wall at x = -1
// and a green one at x = +1, two white boxes, and one rectangular light
// under the ceiling, seen from (0, 0, 3.9) with a 39.3077 degree field of
// view, 256 x 256. It needs no files, no environment map and no lobe
// tables: its materials are Lambertian.

#include "scenes/scene_file.h"

namespace nuld {

LoadedScene makeCornellScene();

}  // namespace nuld
