# Compares nuld and Cycles renders of one scene, K seeds each (K >= 2), for
# the cross-check (README.md in this folder). Run by Blender, which reads EXR:
#   blender -b --factory-startup -P compare.py -- NAME K NULD1..NULDK CYCLES1..CYCLESK
# Prints one CSV row: the scene, nuld's and Cycles' per-channel means (over
# the seeds), their ratios, the pixel RMS of the difference of the two
# renderers' seed averages against the RMS the seed-to-seed noise alone would
# give, nuld's noise over Cycles' (seed-to-seed standard deviations), the
# same per channel, and the 5 % and 95 % points of that ratio when the seeds
# are resampled (bootstrap), which say how far K seeds pin it down.
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
    name, k = argv[0], int(argv[1])
    if k < 2 or len(argv) != 2 + 2 * k:
        print(f"compare: {name}: expected K >= 2 and 2 K files", file=sys.stderr)
        sys.exit(2)
    a = np.stack([load(p) for p in argv[2:2 + k]])
    b = np.stack([load(p) for p in argv[2 + k:]])
    if a.shape != b.shape:
        print(f"compare: {name}: nuld is {a.shape[1:]}, Cycles {b.shape[1:]}", file=sys.stderr)
        sys.exit(2)
    nuld, cycles = a.mean(0), b.mean(0)
    # One render's per-pixel noise variance: the unbiased variance over seeds.
    var_n, var_c = a.var(0, ddof=1), b.var(0, ddof=1)
    rms = np.sqrt(np.mean((nuld - cycles) ** 2))
    # The seed averages' difference, if the renderers agreed.
    rms_noise = np.sqrt((var_n.mean() + var_c.mean()) / k)
    mn, mc = nuld.reshape(-1, 3).mean(0), cycles.reshape(-1, 3).mean(0)
    ratio = mn / mc
    noise = np.sqrt(var_n.mean() / var_c.mean())
    per_channel = np.sqrt(var_n.reshape(-1, 3).mean(0) / var_c.reshape(-1, 3).mean(0))
    rng = np.random.default_rng(1)
    boot = []
    for _ in range(400):
        i, j = rng.integers(0, k, k), rng.integers(0, k, k)
        vc = b[j].var(0, ddof=1).mean()
        if vc > 0:
            boot.append(np.sqrt(a[i].var(0, ddof=1).mean() / vc))
    lo, hi = np.quantile(boot, [0.05, 0.95])
    print(
        f"ROW,{name},"
        + ",".join(f"{v:.6g}" for v in (*mn, *mc, *ratio))
        + f",{rms:.4g},{rms_noise:.4g},{noise:.4g},"
        + ",".join(f"{v:.4g}" for v in per_channel)
        + f",{lo:.3g},{hi:.3g}"
    )


main()
