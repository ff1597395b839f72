#!/usr/bin/env python3
"""The lattice rows of a classic_samplers.sh run as one Markdown table.

Usage: /usr/bin/python3 tools/experiments/lattice_rows.py OUT

For each OUT/SCENE-INTEGRATOR/render.csv: `lattice` and `lattice-baker` at
4 and 16 spp as MSE over `sobol`'s (standard error from both rows' own;
bold when better by two standard errors, "(worse)" when worse by two), and
the study's best classic row at each spp.
"""
import csv
import glob
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from results_page import ratio  # noqa: E402  (the results page's ratio and its error)

SCENES = ["default", "dragon", "cup", "lte-orb"]


def cell(q, se):
    text = f"{q:.3f} +- {se:.3f}"
    if q + 2 * se < 1:
        return f"**{text}**"
    return text + (" (worse)" if q - 2 * se > 1 else "")


def main(out):
    def key(path):
        scene = os.path.basename(os.path.dirname(path)).rsplit("-", 1)[0]
        return (SCENES.index(scene) if scene in SCENES else len(SCENES), path)

    print("| scene | integrator | lattice, 4 spp | lattice, 16 | lattice-baker, 4 "
          "| lattice-baker, 16 | best classic, 4 / 16 spp |")
    print("|---|---|---|---|---|---|---|")
    for path in sorted(glob.glob(os.path.join(out, "*-*", "render.csv")), key=key):
        scene, integrator = os.path.basename(os.path.dirname(path)).rsplit("-", 1)
        with open(path, newline="") as f:
            rows = {(r["backend"], r["spp"]): r for r in csv.DictReader(f)}
        cells = []
        for backend in ("lattice", "lattice-baker"):
            for spp in ("4", "16"):
                r, s = rows[(backend, spp)], rows[("sobol", spp)]
                cells.append(cell(*ratio(float(r["mse"]), float(r["mse_stderr"]),
                                         float(s["mse"]), float(s["mse_stderr"]))))
        best = " / ".join(f"`{rows[('sobol', spp)]['best_classic']}`" for spp in ("4", "16"))
        print(f"| {scene} | {integrator} | " + " | ".join(cells) + f" | {best} |")


if __name__ == "__main__":
    main(sys.argv[1])
