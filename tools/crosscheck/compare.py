# Compares nuld and Cycles renders of one scene, two seeds each, for the
# cross-check (README.md in this folder). Run by Blender, which reads EXR:
#   blender -b --factory-startup -P compare.py -- NAME NULD1 NULD2 CYCLES1 CYCLES2
# Prints one CSV row: the scene, nuld's and Cycles' per-channel means (over
# both seeds), their ratios, the pixel RMS of the difference of the two
# renderers' seed averages against the RMS the seed-to-seed noise alone would
# give, and nuld's noise over Cycles' (seed-to-seed standard deviations).
import sys

import bpy
import numpy as np


def load(path):
    image = bpy.data.images.load(path)
    w, h = image.size
    pixels = np.array(image.pixels[:], dtype=np.float64).reshape(h, w, image.channels)
    return pixels[:, :, :3]


def main():
    argv = sys.argv[sys.argv.index("--") + 1:]
    name, n1, n2, c1, c2 = argv
    a1, a2, b1, b2 = (load(p) for p in (n1, n2, c1, c2))
    if a1.shape != b1.shape:
        print(f"compare: {name}: nuld is {a1.shape}, Cycles {b1.shape}", file=sys.stderr)
        sys.exit(2)
    nuld, cycles = (a1 + a2) / 2, (b1 + b2) / 2
    # One render's per-pixel noise variance from two seeds: E[(x1 - x2)^2] / 2.
    var_n = np.mean((a1 - a2) ** 2) / 2
    var_c = np.mean((b1 - b2) ** 2) / 2
    rms = np.sqrt(np.mean((nuld - cycles) ** 2))
    # The seed averages' difference, if the renderers agreed: (var_n + var_c) / 2.
    rms_noise = np.sqrt((var_n + var_c) / 2)
    mn, mc = nuld.reshape(-1, 3).mean(0), cycles.reshape(-1, 3).mean(0)
    ratio = mn / mc
    print(
        f"ROW,{name},"
        + ",".join(f"{v:.6g}" for v in (*mn, *mc, *ratio))
        + f",{rms:.4g},{rms_noise:.4g},{np.sqrt(var_n / var_c):.4g}"
    )


main()
