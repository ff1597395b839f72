#!/usr/bin/env python3
"""Low and high bands of each row's error spectrum, over sobol's.

Usage: /usr/bin/python3 tools/experiments/spectrum_bands.py OUT [WORDS]

For each study OUT/SCENE-INTEGRATOR (classic_samplers.sh writes them) and
spp 4 and 16: the error power of SCENE/WORD_sppN_spectrum.csv (the study's
radially averaged power spectrum of the error's luminance, the repeats'
mean) summed over the rings below 0.125 cycles per pixel (what a 1-pixel
Gaussian keeps: the error a viewer sees) and over those at 0.375 and above,
each ring weighted by its radius (the frequencies it holds), as a ratio to
sobol's. WORDS: comma-separated (default zsobol,pmj02,lattice,lattice-baker).
The study keeps only the repeats' mean spectrum, so these ratios have no
standard error: read them beside the MSE and screen ratios, which do.
"""
import csv
import glob
import os
import sys


def bands(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    low = high = 0.0
    for r in rows:
        power = float(r["power"]) * max(int(r["radius"]), 1)
        frequency = float(r["cycles_per_pixel"])
        if frequency < 0.125:
            low += power
        elif frequency >= 0.375:
            high += power
    return low, high


def main(out, words):
    print("| scene | integrator | spp | " + " | ".join(f"{w}: low / high" for w in words) + " |")
    print("|---|---|---|" + "---|" * len(words))
    for study in sorted(glob.glob(os.path.join(out, "*-*", ""))):
        scene, integrator = os.path.basename(os.path.dirname(study)).rsplit("-", 1)
        for spp in ("4", "16"):
            def of(word):
                return bands(os.path.join(study, scene, f"{word}_spp{spp}_spectrum.csv"))
            s = of("sobol")
            cells = [f"{b[0] / s[0]:.2f} / {b[1] / s[1]:.2f}" for b in map(of, words)]
            print(f"| {scene} | {integrator} | {spp} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main(sys.argv[1],
         (sys.argv[2] if len(sys.argv) > 2 else "zsobol,pmj02,lattice,lattice-baker").split(","))
